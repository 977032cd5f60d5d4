#include "hard_cases.hpp"

#include <nlohmann/json.hpp>
#include <stdexcept>

namespace vs::testing {

namespace {
using json = nlohmann::json;

json vec(double x, double y, double z) { return json::array({x, y, z}); }

// A ground plane, a box occluder and a sphere, a point light above and in front, in fog.
json baseScene() {
  return {{"geometry",
           json::array({{{"generator", "plane"}, {"params", {{"center", vec(0, 0, 0)}, {"size", {12, 12}}}}},
                        {{"generator", "box"}, {"params", {{"center", vec(-1, 0.75, 0)}, {"size", vec(1, 1.5, 1)}}}},
                        {{"generator", "sphere"}, {"params", {{"center", vec(1.2, 0.8, -0.5)}, {"radius", 0.7}, {"segments", 24}}}}})},
          {"camera", {{"position", vec(0, 1.5, 6)}, {"target", vec(0, 1, 0)}, {"fov_y_deg", 55}, {"near", 0.05}, {"far", 30}}},
          {"light", {{"type", "point"}, {"position", vec(0, 3, -2)}, {"intensity", 30}}},
          {"medium", {{"sigma_s", 0.08}, {"sigma_a", 0.02}, {"phase", "isotropic"}}}};
}

json triangle(json a, json b, json c) {
  return {{"generator", "triangle"}, {"params", {{"vertices", json::array({a, b, c})}}}};
}

HardCase make(std::string name, const json& scene, bool singular = false) {
  return {std::move(name), scene.dump(), singular};
}

std::vector<HardCase> build() {
  std::vector<HardCase> cases;
  json s = baseScene();
  cases.push_back(make("epipole_on_screen", s));

  s = baseScene();
  s["light"] = {{"type", "spot"}, {"position", vec(0, 3, -2)}, {"target", vec(0, 0, 2)}, {"intensity", 60},
                {"spot_inner_deg", 30}, {"spot_outer_deg", 45}};
  cases.push_back(make("spot_epipole_on_screen", s));

  s = baseScene();
  s["light"]["position"] = vec(9, 3, 0);
  cases.push_back(make("epipole_off_screen", s));

  s = baseScene();
  s["light"]["position"] = vec(0, 3, 10);
  cases.push_back(make("epipole_behind_camera", s));

  s = baseScene();
  s["camera"]["target"] = s["light"]["position"];
  cases.push_back(make("looking_at_light", s));

  s = baseScene();
  s["light"]["position"] = s["camera"]["position"];
  cases.push_back(make("light_at_eye", s, true));

  s = baseScene();
  s["light"]["position"] = vec(1e-4, 1.5, 6);
  cases.push_back(make("light_within_1e-4_of_eye", s, true));

  // Camera looks along -Z tilted down; the sun travels along (anti-)parallel to that.
  json forward = vec(0, -0.5 / 6.0828, -6 / 6.0828);
  s = baseScene();
  s["light"] = {{"type", "directional"}, {"direction", forward}, {"intensity", 2}};
  cases.push_back(make("directional_parallel_to_view", s));

  s = baseScene();
  s["light"] = {{"type", "directional"}, {"direction", vec(0, 0.5 / 6.0828, 6 / 6.0828)}, {"intensity", 2}};
  cases.push_back(make("directional_antiparallel_to_view", s));

  // A triangle between the eye and the light that covers the light's image (the epipole).
  s = baseScene();
  s["geometry"].push_back(triangle(vec(-1.5, 1.6, 0.5), vec(1.5, 1.6, 0.5), vec(0, 4.5, -0.5)));
  cases.push_back(make("triangle_covers_epipole", s));

  // A triangle right of the epipole that crosses the horizontal line through it (theta = 0).
  s = baseScene();
  s["geometry"].push_back(triangle(vec(0.6, 2.0, -1.0), vec(2.5, 2.4, -1.2), vec(1.2, 3.8, -1.5)));
  cases.push_back(make("triangle_crosses_theta_seam", s));

  s = baseScene();
  s["geometry"].push_back({{"generator", "box"}, {"params", {{"center", vec(0, 3.5, -2)}, {"size", vec(1, 1, 1)}}}});
  cases.push_back(make("occluder_touching_light", s));

  s = baseScene();
  s["camera"]["position"] = vec(0, 0.01, 6);
  s["camera"]["target"] = vec(0, 0.0, -6);
  s["light"]["position"] = vec(0, 0.3, -4);
  cases.push_back(make("grazing_surfaces", s));

  for (auto [name, sigmaS, sigmaA] : {std::tuple<const char*, double, double>{"sigma_t_0", 0.0, 0.0},
                                      {"sigma_t_1e-6", 1e-6, 0.0},
                                      {"sigma_t_1e3", 500.0, 500.0},
                                      {"sigma_s_0", 0.0, 0.05}}) {
    s = baseScene();
    s["medium"] = {{"sigma_s", sigmaS}, {"sigma_a", sigmaA}, {"phase", "isotropic"}};
    cases.push_back(make(name, s));
  }

  s = baseScene();
  s["camera"]["position"] = vec(-1, 0.75, 0);  // the centre of the box
  s["camera"]["target"] = vec(0, 1, -5);
  cases.push_back(make("camera_inside_occluder", s));

  s = baseScene();
  s["geometry"] = json::array();
  cases.push_back(make("empty_scene", s));

  s = baseScene();
  s["geometry"] = json::array({triangle(vec(-1, 0.5, 0), vec(1, 0.5, 0), vec(0, 2.5, -0.5))});
  cases.push_back(make("single_triangle", s));

  s = baseScene();
  s["geometry"].push_back(triangle(vec(0, 1, 0), vec(1, 1, 0), vec(2, 1, 0)));  // zero area
  s["geometry"].push_back(triangle(vec(0, 1, 0), vec(0, 1, 0), vec(0, 1, 0)));  // a point
  s["geometry"].push_back(triangle(json::array({"nan", 1, 0}), vec(1, 2, 0), vec(0, 2, 1)));
  s["geometry"].push_back(triangle(json::array({"inf", 1, 0}), vec(1, 2, 0), vec(0, 2, 1)));
  cases.push_back(make("degenerate_and_nan_vertices", s));

  s = baseScene();
  s["camera"]["near"] = 1e-4;
  s["camera"]["far"] = 100.0;
  cases.push_back(make("near_far_ratio_1e6", s));

  // Everything moved 1e5 units away from the origin.
  s = baseScene();
  const double off = 1e5;
  for (auto& g : s["geometry"]) {
    auto& p = g["params"];
    if (p.contains("center")) p["center"] = vec(p["center"][0].get<double>() + off, p["center"][1], p["center"][2].get<double>() + off);
  }
  s["camera"]["position"] = vec(off, 1.5, 6 + off);
  s["camera"]["target"] = vec(off, 1, off);
  s["light"]["position"] = vec(off, 3, -2 + off);
  cases.push_back(make("coordinates_1e5", s));

  // Volume data (methods without it are Unsupported here and skip).
  auto withVolume = [](json volume) {
    json v = baseScene();
    v["volumes"] = json::array({volume});
    return v;
  };
  json bucky = {{"generator", "bucky"}, {"box_min", vec(-1.5, 0.2, -1)}, {"box_max", vec(0.5, 2.2, 1)}, {"sigma_s", 2.0}, {"sigma_a", 0.2}};
  cases.push_back(make("volume_in_view", withVolume(bucky)));
  json around = bucky;
  around["box_min"] = vec(-2, 0.5, 3);
  around["box_max"] = vec(2, 2.5, 8);
  cases.push_back(make("camera_inside_volume", withVolume(around)));
  json nearPlane = bucky;
  nearPlane["box_min"] = vec(-1, 1, 4);
  nearPlane["box_max"] = vec(1, 2, 5.95);  // the camera's near plane is at z = 5.95
  cases.push_back(make("volume_touching_near_plane", withVolume(nearPlane)));
  json empty = bucky;
  empty["density_scale"] = 0.0;
  cases.push_back(make("volume_density_zero", withVolume(empty)));
  std::vector<double> spike(27, 0.0);
  spike[13] = 1e4;
  json dense = {{"dims", {3, 3, 3}}, {"density", spike}, {"box_min", vec(-0.5, 1, -0.5)}, {"box_max", vec(0.5, 2, 0.5)},
                {"sigma_s", 1.0}, {"sigma_a", 0.1}};
  cases.push_back(make("volume_one_voxel_density_1e4", withVolume(dense), true));
  json single = {{"dims", {1, 1, 1}}, {"density", {0.5}}, {"box_min", vec(-2, 0, -2)}, {"box_max", vec(2, 2, 0)},
                 {"sigma_s", 0.5}, {"sigma_a", 0.1}};
  cases.push_back(make("volume_1x1x1", withVolume(single)));
  json aroundLight = bucky;  // the light (0, 3, -2) inside the box
  aroundLight["box_min"] = vec(-1, 2, -3);
  aroundLight["box_max"] = vec(1, 4, -1);
  cases.push_back(make("light_inside_volume", withVolume(aroundLight)));
  json behind = bucky;  // the camera (0, 1.5, 6) looks towards -z
  behind["box_min"] = vec(-1, 0.5, 7);
  behind["box_max"] = vec(1, 2.5, 9);
  cases.push_back(make("volume_behind_camera", withVolume(behind)));
  json grazing = bucky;  // the box's top face in the plane of the light
  grazing["box_max"] = vec(0.5, 3.0, 1);
  cases.push_back(make("light_grazing_volume", withVolume(grazing)));
  json huge = {{"generator", "cloud"}, {"scale", 0.5}, {"seed", 5}, {"box_min", vec(-60, -1, -60)},
               {"box_max", vec(60, 25, 60)}, {"sigma_s", 0.1}, {"sigma_a", 0.01}};
  cases.push_back(make("volume_larger_than_view", withVolume(huge)));

  // Semi-transparent occluders (methods without them skip).
  for (double opacity : {0.0, 0.5, 1.0}) {
    s = baseScene();
    s["geometry"][1]["opacity"] = opacity;  // the box
    s["geometry"][2]["opacity"] = opacity;  // the sphere
    cases.push_back(make(opacity == 0.0 ? "opacity_0" : opacity == 1.0 ? "opacity_1_declared" : "opacity_half", s));
  }
  s = baseScene();
  s["geometry"].push_back({{"generator", "layers"},
                           {"params", {{"center", vec(0.3, 0.6, -1.2)}, {"size", 0.6}, {"count", 1000}, {"spacing", 0.0005}}},
                           {"opacity", 0.01},
                           {"transmittance_color", vec(0.5, 0.3, 0.1)}});
  cases.push_back(make("1000_stacked_layers", s));
  cases.back().width = 32;  // 34 s a run of the stability test at 64x48 (raymarch's three renders)
  cases.back().height = 24;

  // Area lights (methods without them skip).
  auto rect = [](double side) {
    return json{{"type", "rect"}, {"position", vec(0, 3, -2)}, {"direction", vec(0, -1, 0.2)}, {"width", side},
                {"height", side}, {"intensity", 30.0 / (side * side)}};
  };
  s = baseScene();
  s["light"] = rect(1.0);
  cases.push_back(make("area_light", s));
  s = baseScene();
  s["light"] = rect(1e-6);
  cases.push_back(make("area_light_size_1e-6", s));
  s = baseScene();
  s["light"] = rect(1.0);
  s["light"]["direction"] = vec(0, 1, 0);  // one-sided, facing the sky: nothing is lit
  cases.push_back(make("area_light_facing_away", s));
  s = baseScene();
  s["light"] = rect(1.0);
  s["light"]["position"] = vec(-1, 1.2, 0);  // inside the box
  cases.push_back(make("area_light_inside_geometry", s));
  s = baseScene();
  s["light"] = {{"type", "disk"}, {"position", vec(1.2, 1.6, -0.5)}, {"direction", vec(0, -1, 0)}, {"radius", 0.3},
                {"intensity", 80}, {"two_sided", true}};  // touching the sphere's top
  cases.push_back(make("area_light_touching_occluder", s));
  return cases;
}
// A track {"times": times, "values": values} with its interpolation.
json track(json times, json values, const char* interpolation = "linear") {
  return {{"times", std::move(times)}, {"values", std::move(values)}, {"interpolation", interpolation}};
}

std::vector<HardCase> buildTemporal() {
  std::vector<HardCase> cases;
  auto moving = [](json scene, json animation) {
    animation["duration"] = 1.0;
    animation["fps"] = 4.0;
    scene["animation"] = std::move(animation);
    return scene;
  };
  // The light enters the view through its right border (the camera's half-angle is about 36
  // degrees horizontally at 4:3): the epipole crosses the screen edge between frames.
  cases.push_back(make("epipole_crosses_border",
                       moving(baseScene(), {{"light", {{"position", track({0, 1}, {vec(9, 3, 0), vec(1.5, 3, 0)})}}}})));
  // The light passes through the box occluder (x in [-1.5, -0.5], y in [0, 1.5]).
  cases.push_back(make("light_through_occluder",
                       moving(baseScene(), {{"light", {{"position", track({0, 1}, {vec(-3, 0.75, 0), vec(1, 0.75, 0)})}}}})));
  // The camera walks from outside a volume into it and on (the box spans z in [1, 4]).
  json volumeScene = baseScene();
  volumeScene["volumes"] = json::array({{{"generator", "bucky"}, {"box_min", vec(-2, 0.5, 1)}, {"box_max", vec(2, 2.5, 4)},
                                         {"sigma_s", 2.0}, {"sigma_a", 0.2}}});
  cases.push_back(make("camera_crosses_volume_boundary",
                       moving(volumeScene, {{"camera", {{"position", track({0, 1}, {vec(0, 1.5, 6), vec(0, 1.5, 2.5)})}}}})));
  // Keys a microsecond apart: a jump, through every interpolation's tangent arithmetic.
  cases.push_back(make("keys_a_microsecond_apart",
                       moving(baseScene(), {{"light", {{"position", track({0, 0.5, 0.500001, 1},
                                                                           {vec(-2, 3, -2), vec(-2, 3, -2), vec(2, 2, -1), vec(2, 2, -1)},
                                                                           "catmull-rom")}}},
                                            {"camera", {{"fov_y_deg", track({0, 0.5, 0.500001, 1}, {55, 55, 70, 70}, "step")}}}})));
  return cases;
}

const HardCase& find(const std::vector<HardCase>& cases, const std::string& name) {
  for (const auto& c : cases)
    if (c.name == name) return c;
  throw std::invalid_argument("no hard case " + name);
}
}  // namespace

const std::vector<HardCase>& temporalHardCases() {
  static const std::vector<HardCase> cases = buildTemporal();
  return cases;
}

const HardCase& temporalHardCase(const std::string& name) { return find(temporalHardCases(), name); }

const std::vector<HardCase>& hardCases() {
  static const std::vector<HardCase> cases = build();
  return cases;
}

const HardCase& hardCase(const std::string& name) { return find(hardCases(), name); }

}  // namespace vs::testing
