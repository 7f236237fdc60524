// gl_bench SCENE.json [WxH] [textures] [physical|faithful]: the GL tracer's benchmark on a scene
// saved by `brushtrace dump --json`, without the importers. The importers link OpenImageIO,
// whose dependencies (over 300 MB) cannot travel to the GPU machine (scripts/gpu-check.sh);
// this program needs only GL, so the benchmark map is imported here and its dump carried.
// Textures are not in the dump: every material is the untextured placeholder.
#include "renderer/gl/gl_bench.h"
#include "renderer/gl/gl_error.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <map>

namespace {

bt::dvec3 vec(const nlohmann::json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }

// The inverse of app/scene_json.cpp's dumpJson, for what the tracer reads.
bt::Scene sceneFromDump(const nlohmann::json& dump) {
  bt::Scene scene;
  scene.format = dump.value("dialect", "");
  std::map<std::string, uint32_t> materials;
  for (const auto& e : dump.at("entities")) {
    bt::Entity entity;
    entity.line = e.value("line", 0);
    for (const auto& kv : e.at("keys")) entity.keys.emplace_back(kv.at(0).get<std::string>(), kv.at(1).get<std::string>());
    entity.firstBrush = static_cast<uint32_t>(scene.brushes.size());
    for (const auto& b : e.at("brushes")) {
      bt::Brush brush;
      brush.line = b.value("line", 0);
      brush.entity = static_cast<uint32_t>(scene.entities.size());
      brush.firstFace = static_cast<uint32_t>(scene.faces.size());
      for (const auto& f : b.at("faces")) {
        bt::Face face;
        face.line = f.value("line", 0);
        face.brush = static_cast<uint32_t>(scene.brushes.size());
        face.texture = f.at("texture").get<std::string>();
        auto [it, added] = materials.emplace(face.texture, static_cast<uint32_t>(scene.materials.size()));
        if (added) scene.materials.push_back(bt::Material{.name = face.texture});
        face.material = it->second;
        face.plane = {vec(f.at("normal")), f.at("dist").get<double>()};
        face.frame = {vec(f.at("origin")), vec(f.at("tangent")), vec(f.at("bitangent"))};
        for (const auto& p : f.at("winding")) {
          face.winding.push_back(vec(p));
          brush.bounds.grow(face.winding.back());
        }
        scene.faces.push_back(std::move(face));
      }
      brush.faceCount = static_cast<uint32_t>(scene.faces.size()) - brush.firstFace;
      scene.bounds.grow(brush.bounds);
      scene.brushes.push_back(std::move(brush));
    }
    entity.brushCount = static_cast<uint32_t>(scene.brushes.size()) - entity.firstBrush;
    scene.entities.push_back(std::move(entity));
  }
  return scene;
}

} // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: gl_bench SCENE.json [WxH] [auto|bindless|arrays] [physical|faithful] [seconds]\n");
    return 2;
  }
  bt::gl::GlBenchSettings settings;
  if (argc > 2 && std::sscanf(argv[2], "%dx%d", &settings.width, &settings.height) != 2) return 2;
  if (argc > 3) {
    auto mode = bt::gl::parseTextureMode(argv[3]);
    if (!mode) return 2;
    settings.textures = *mode;
  }
  if (argc > 4) settings.physical = std::string(argv[4]) != "faithful";
  if (argc > 5) settings.seconds = std::atof(argv[5]);
  try {
    std::ifstream in(argv[1]);
    if (!in) throw std::runtime_error(std::string("cannot open ") + argv[1]);
    const nlohmann::json dump = nlohmann::json::parse(in);
    const bt::Scene scene = sceneFromDump(dump);
    fmt::print("scene: {} ({} brushes, {} faces, {} materials, untextured)\n", argv[1], scene.brushes.size(),
               scene.faces.size(), scene.materials.size());
    // The parsed dump stands in for the import (a .map's parse is timed by bench_map_import).
    return bt::gl::runGlBench([&] { return sceneFromDump(dump); }, settings);
  } catch (const std::exception& e) {
    fmt::print(stderr, "gl_bench: {}\n", e.what());
    return 1;
  }
}
