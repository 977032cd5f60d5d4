// Result folders written by hand for the report's tests: no GL, every column as the harness
// writes it (harness/io/results.hpp), values chosen so that the CSV order is not the time order.
#pragma once
#include <string>
#include <vector>

namespace vs::testing {

struct FixtureRow {
  std::string method, params, series, status, reason;
  std::string scatterMs, frameMs, lsRmse, lsRelmse;
  std::string speedupUniform;  // empty: no equal-quality columns
};

// The rows of the small fixture: raymarch (two series), minmax, vsv, an Unsupported dsm and a
// failed slicemap whose reason holds a comma, quotes and markup.
std::vector<FixtureRow> fixtureRows();

// A shootout folder: runs.csv, passes.csv, meta.json and, with `images`, tiny PNGs under
// images/SCENE/ as `vshadow shootout` names them; with `frames`, frames.csv of an animated run.
void writeShootoutFixture(const std::string& dir, const std::string& scene, bool images, bool frames);

// A sweep-sized folder: `rows` Success rows (and a few Unsupported ones) of one scene, passes.csv
// with four passes per row, no images.
void writeLargeFixture(const std::string& dir, int rows);

}  // namespace vs::testing
