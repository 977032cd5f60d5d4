#include "bad_inputs.hpp"

#include "fixtures.hpp"
#include "gl_test.hpp"

namespace vs::testing {

const std::vector<BadInput>& badInputs() {
  static const std::vector<BadInput> inputs = {
      {"missing_scene", {"run", "--scene", "%DIR%/nope.json", "--method", "raymarch"}, "nope.json",
       "scene file that does not exist"},
      {"malformed_json", {"run", "--scene", "%DIR%/malformed.json", "--method", "raymarch"}, "malformed.json",
       "scene JSON with a syntax error"},
      {"unknown_scene_key", {"run", "--scene", "%DIR%/unknown-key.json", "--method", "raymarch"}, "colour",
       "scene JSON with a misspelt key"},
      {"malformed_gltf", {"run", "--scene", "%DIR%/bad-gltf.json", "--method", "raymarch"}, "broken.gltf",
       "glTF file that is not valid JSON"},
      {"missing_gltf", {"run", "--scene", "%DIR%/missing-gltf.json", "--method", "raymarch"}, "nowhere.gltf",
       "glTF file that does not exist"},
      {"truncated_gltf_buffer", {"run", "--scene", "%DIR%/truncated-gltf.json", "--method", "raymarch"},
       "truncated.gltf", "glTF whose .bin is shorter than its declared byteLength"},
      {"nan_param", {"run", "--scene", "spheres", "--method", "raymarch:steps=nan"}, "steps=nan",
       "NaN as an integer parameter"},
      {"nan_shadow_map", {"run", "--scene", "spheres", "--method", "raymarch:sm=nan"}, "sm=nan",
       "NaN as the shadow-map size"},
      {"unknown_method", {"run", "--scene", "spheres", "--method", "nosuch"}, "unknown method 'nosuch'",
       "method that is not registered"},
      {"unknown_key", {"run", "--scene", "spheres", "--method", "raymarch:stepz=4"}, "stepz",
       "parameter the method does not have"},
      {"out_of_range", {"run", "--scene", "spheres", "--method", "raymarch:steps=0"}, "out of range",
       "parameter below its range"},
      {"not_a_number", {"run", "--scene", "spheres", "--method", "raymarch:steps=many"}, "not an integer",
       "parameter that is not a number"},
      {"malformed_spec", {"run", "--scene", "spheres", "--method", "raymarch:steps"}, "not key=value",
       "method spec without a value"},
      {"shadow_map_over_limit", {"run", "--scene", "spheres", "--method", "raymarch:sm=1048576"}, "out of range",
       "shadow map larger than GL_MAX_TEXTURE_SIZE"},
      {"size_over_gl_limit", {"run", "--scene", "spheres", "--method", "raymarch", "--size", "999999x16"}, "exceeds",
       "image larger than the GL limits"},
      {"malformed_size", {"run", "--scene", "spheres", "--method", "raymarch", "--size", "big"}, "--size",
       "--size that is not WxH"},
      {"unknown_option", {"run", "--scene", "spheres", "--method", "raymarch", "--colour"}, "colour",
       "command-line option that does not exist"},
      {"bad_frames", {"run", "--scene", "spheres", "--method", "raymarch", "--frames", "0"}, "frames",
       "--frames 0"},
      {"min_time_without_warmup", {"run", "--scene", "spheres", "--method", "raymarch", "--warmup", "0", "--min-time", "100"},
       "--min-time needs --warmup", "--min-time without a warm-up frame to size the run"},
      {"unknown_reference_method", {"run", "--scene", "spheres", "--method", "raymarch", "--reference", "nosuch:steps=1"},
       "nosuch", "--reference naming an unknown method"},
      {"raw_volume_too_short", {"run", "--scene", "%DIR%/short-volume.json", "--method", "raymarch"}, "need 64",
       "raw volume file shorter than dims x voxel size"},
      {"raw_volume_too_long", {"run", "--scene", "%DIR%/long-volume.json", "--method", "raymarch"}, "need 4",
       "raw volume file longer than dims x voxel size"},
      {"unknown_voxel_type", {"run", "--scene", "%DIR%/u12-volume.json", "--method", "raymarch"}, "u12",
       "raw volume of an unknown voxel type"},
      {"volume_dims_zero", {"run", "--scene", "%DIR%/zero-volume.json", "--method", "raymarch"}, "dims[1]",
       "raw volume with a dimension of 0"},
      {"nan_density", {"run", "--scene", "%DIR%/nan-volume.json", "--method", "raymarch"}, "nan",
       "NaN density in a float volume file"},
      {"too_many_volumes", {"run", "--scene", "%DIR%/five-volumes.json", "--method", "raymarch"}, "at most 4",
       "more volumes than texture units are set aside for"},
      {"opacity_out_of_range", {"run", "--scene", "%DIR%/opacity.json", "--method", "raymarch"}, "opacity",
       "geometry opacity outside [0, 1]"},
      {"area_light_size_zero", {"run", "--scene", "%DIR%/flat-light.json", "--method", "raymarch"}, "light.width",
       "rect light of width 0"},
      {"corrupt_embedded_image", {"run", "--scene", "%DIR%/corrupt-image.json", "--method", "raymarch"}, "corrupt PNG",
       "glTF whose embedded (buffer-view) alpha texture is a corrupt PNG"},
      {"data_uri_not_an_image", {"run", "--scene", "%DIR%/data-uri-text.json", "--method", "raymarch"}, "cannot decode",
       "glTF whose data: URI image holds text, not an image"},
      {"mtl_dissolve_not_a_number", {"run", "--scene", "%DIR%/mtl-d.json", "--method", "raymarch"}, "glass.mtl:3",
       "OBJ whose MTL sets `d` to a word, not a number"},
      // An OBJ without its MTL is not bad input: it loads with a warning (tests/cli_tests.cpp).
      {"unwritable_output", {"run", "--scene", "spheres", "--method", "raymarch", "--out", "%DIR%/a-file/results"},
       "a-file/results", "--out below a regular file (cannot be created)"},
  };
  return inputs;
}

void writeBadInputFixtures(const std::string& dir) {
  writeFile(dir + "/malformed.json", "{ \"camera\": [1, 2,, }");
  writeFile(dir + "/unknown-key.json", R"({"geometry": [], "camera": {}, "light": {"type": "point"}, "colour": 1})");
  const std::string camera = R"("camera": {"position": [0, 1, 5], "target": [0, 0, 0]})";
  writeFile(dir + "/bad-gltf.json", R"({"geometry": [{"gltf": "broken.gltf"}], )" + camera + "}");
  writeFile(dir + "/broken.gltf", "{ \"asset\": {\"version\": \"2.0\"}, \"buffers\": [ ");
  writeFile(dir + "/missing-gltf.json", R"({"geometry": [{"gltf": "nowhere.gltf"}], )" + camera + "}");
  writeFile(dir + "/short.bin", std::string(12, '\0'));
  writeFile(dir + "/truncated.gltf", R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "buffers": [{"uri": "short.bin", "byteLength": 36}], "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]}]})");
  writeFile(dir + "/truncated-gltf.json", R"({"geometry": [{"gltf": "truncated.gltf"}], )" + camera +
                                               R"(, "light": {"type": "point", "position": [0, 3, 0], "intensity": 1}})");
  writeFile(dir + "/a-file", "not a folder");
  const std::string light = R"("light": {"type": "point", "position": [0, 3, 0], "intensity": 1})";
  auto volumeScene = [&](const std::string& volume) {
    return R"({"geometry": [], )" + camera + ", " + light + R"(, "volumes": [)" + volume + "]}";
  };
  const std::string box = R"("box_min": [-1, 0, -1], "box_max": [1, 2, 1])";
  writeFile(dir + "/eight-bytes.raw", std::string(8, '\x01'));
  writeFile(dir + "/short-volume.json", volumeScene(R"({"raw": "eight-bytes.raw", "type": "u8", "dims": [4, 4, 4], )" + box + "}"));
  writeFile(dir + "/long-volume.json", volumeScene(R"({"raw": "eight-bytes.raw", "type": "u8", "dims": [2, 2, 1], )" + box + "}"));
  writeFile(dir + "/u12-volume.json", volumeScene(R"({"raw": "eight-bytes.raw", "type": "u12", "dims": [2, 2, 2], )" + box + "}"));
  writeFile(dir + "/zero-volume.json", volumeScene(R"({"raw": "eight-bytes.raw", "type": "u8", "dims": [2, 0, 2], )" + box + "}"));
  writeFile(dir + "/nan.raw", std::string("\x00\x00\xc0\x7f", 4));  // a quiet NaN, little endian
  writeFile(dir + "/nan-volume.json", volumeScene(R"({"raw": "nan.raw", "type": "f32", "dims": [1, 1, 1], )" + box + "}"));
  std::string five;
  for (int i = 0; i < 5; ++i) five += std::string(i ? ", " : "") + R"({"dims": [1, 1, 1], "density": [1], )" + box + "}";
  writeFile(dir + "/five-volumes.json", volumeScene(five));
  writeFile(dir + "/opacity.json", R"({"geometry": [{"generator": "plane", "opacity": 2}], )" + camera + ", " + light + "}");
  // Embedded alpha textures that cannot be decoded: a .glb whose PNG (in a buffer view) is cut to
  // garbage after its header, and a .gltf whose data: URI image is text.
  const std::vector<float> alpha = {0.25f, 1.0f, 0.5f, 0.0f};
  std::string glb = readFile(writeAlphaQuadGltf(dir, "corrupt-image", "BLEND", 0.0, 2, 2, alpha, 2.0, 1.0, "glb"));
  for (size_t i = glb.find("\x89PNG") + 16; i < glb.size(); ++i) glb[i] = 'x';  // past the signature and IHDR length
  writeFile(dir + "/corrupt-image.glb", glb);
  writeFile(dir + "/corrupt-image.json", R"({"geometry": [{"gltf": "corrupt-image.glb"}], )" + camera + ", " + light + "}");
  std::string gltf = readFile(writeAlphaQuadGltf(dir, "data-uri-text", "BLEND", 0.0, 2, 2, alpha, 2.0, 1.0, "data-uri"));
  const std::string prefix = "data:image/png;base64,";
  const size_t uri = gltf.find(prefix) + prefix.size();
  gltf.replace(uri, gltf.find('"', uri) - uri, base64({'n', 'o', 't', ' ', 'a', 'n', ' ', 'i', 'm', 'a', 'g', 'e'}));
  writeFile(dir + "/data-uri-text.gltf", gltf);
  writeFile(dir + "/data-uri-text.json", R"({"geometry": [{"gltf": "data-uri-text.gltf"}], )" + camera + ", " + light + "}");
  // An MTL whose dissolve is a word: tinyobjloader would read 0, an invisible surface.
  writeFile(dir + "/glass.obj", "mtllib glass.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl glass\nf 1 2 3\n");
  writeFile(dir + "/glass.mtl", "newmtl glass\nKd 0.2 0.3 0.4\nd half\n");
  writeFile(dir + "/mtl-d.json", R"({"geometry": [{"obj": "glass.obj"}], )" + camera + ", " + light + "}");
  writeFile(dir + "/flat-light.json", R"({"geometry": [], )" + camera +
                                          R"(, "light": {"type": "rect", "position": [0, 3, 0], "direction": [0, -1, 0], "width": 0, "height": 1, "intensity": 1}})");
}

std::vector<std::string> badInputArgs(const BadInput& bad, const std::string& dir) {
  std::vector<std::string> args;
  for (std::string a : bad.args) {
    auto pos = a.find("%DIR%");
    if (pos != std::string::npos) a.replace(pos, 5, dir);
    args.push_back(a);
  }
  return args;
}

}  // namespace vs::testing
