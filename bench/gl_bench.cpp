// gl_bench LEVEL [WxH] [textures] [physical|faithful] [seconds] [converge [SPP [floor] [dump DIR]] | rays [binary PATH] [BT_RB_...]]: the GL tracer's
// benchmark
// (`brushtrace bench`) in a program that links no OpenImageIO, whose libraries (over 300 MB)
// cannot travel to the GPU machine (scripts/gpu-check.sh): the level is imported with
// bt_importers_portable (bt_importers, which reads loose images without OpenImageIO).
// LEVEL `generated:N` is tests/bvh's generated level of about N brushes (bench_bvh's, seed 1)
// with the camera in its first room, for the ray rates of a level larger than the GPU's L2
// (issue 20: 500,000 brushes); it has no lights.
#include "importers/import.h"
#include "renderer/gl/gl_bench.h"
#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_program.h"
#include "renderer/image_output.h"
#include "tests/bvh/generated_scenes.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>

namespace {

// Whether the shaders name a ray benchmark switch (they are its only list): a misspelt one would
// otherwise time the plain walk under its name.
bool switchInShaders(const std::string& name) {
  if (!std::ranges::all_of(name, [](char c) {
        return std::isupper(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_';
      }))
    return false;
  const std::regex word("\\b" + name + "\\b");
  for (const bt::gl::ShaderFile& file : bt::gl::embeddedShaders())
    if (std::regex_search(file.source, word)) return true;
  return false;
}

} // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(
        stderr,
        "usage: gl_bench LEVEL [WxH] [auto|bindless|arrays] [physical|faithful] [seconds] [converge [REFERENCE_SPP [floor] [dump DIR]] "
        "| rays [binary PATH] [BT_RB_SWITCH[=VALUE] ...]]\n");
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
  // Issue 18's time to converged (brushtrace bench --time-to-converged), for the device machine,
  // where brushtrace itself does not travel.
  // The ray rates alone (brushtrace bench --rays-only): a Quake 3 level's also without its curves.
  if (argc > 6 && std::string(argv[6]) == "rays") {
    settings.raysOnly = true;
    // `rays [binary PATH] [DEFINE[=VALUE] ...]`: timed with raybench.comp's measurement switches
    // (shaders/trace.glsl BT_RB_*), the program's driver binary written to PATH.
    int next = 7;
    if (argc > next + 1 && std::string(argv[next]) == "binary") settings.rayBenchBinary = argv[next + 1], next += 2;
    for (; next < argc; ++next) {
      std::string define = argv[next];
      const std::string name = define.substr(0, define.find('='));
      if (!name.starts_with("BT_RB_") || !switchInShaders(name)) {
        std::fprintf(stderr, "gl_bench: '%s' is not a ray benchmark switch (BT_RB_..., see shaders/trace.glsl)\n", argv[next]);
        return 2;
      }
      if (const size_t equals = define.find('='); equals != std::string::npos) define[equals] = ' ';
      settings.rayBenchDefines.push_back(define);
    }
  } else if (argc > 6) {
    if (std::string(argv[6]) != "converge") return 2;
    settings.timeToConverged = true;
    if (argc > 7) settings.referenceSpp = std::atoi(argv[7]);
    if (settings.referenceSpp < 4) return 2;
    int next = 8;
    if (argc > next && std::string(argv[next]) == "floor") settings.referenceFloor = true, ++next;
    // The reference and each step's raw image (AOVs and second moment with it) as EXRs in DIR:
    // the denoiser lab's input (issue 18), from the GPU where the CPU would take hours.
    if (argc > next) {
      if (std::string(argv[next]) != "dump" || argc <= next + 1) return 2;
      const std::filesystem::path dir = argv[next + 1];
      std::filesystem::create_directories(dir);
      settings.keep = [dir](const bt::RenderImage& image, const std::string& name) {
        bt::writeImage((dir / (name + ".exr")).string(), image, {});
      };
    }
  }
  try {
    const std::string level = argv[1];
    if (level.starts_with("generated:")) {
      bt::test::GeneratedLevel generated = bt::test::generateLevel(std::stoi(level.substr(10)), 1);
      const auto eye = generated.openPoints.at(0);
      generated.scene.entities.push_back(
          {.keys = {{"classname", "info_player_start"}, {"origin", fmt::format("{} {} {}", eye.x, eye.y, eye.z)}}});
      fmt::print("scene: {} ({} brushes, {} faces)\n", level, generated.scene.brushes.size(), generated.scene.faces.size());
      return bt::gl::runGlBench([&](const bt::gl::EntitiesRead&) { return generated.scene; }, settings);
    }
    const bt::Scene scene = bt::importScene(level, {});
    size_t placeholders = 0;
    for (const bt::Material& m : scene.materials) placeholders += m.sourcePath.empty();
    fmt::print("scene: {} ({} brushes, {} faces, {} materials, {} of them placeholders)\n", level, scene.brushes.size(), scene.faces.size(),
               scene.materials.size(), placeholders);
    return bt::gl::runGlBench([&](const bt::gl::EntitiesRead& entitiesRead) { return bt::importScene(level, {}, entitiesRead); }, settings);
  } catch (const std::exception& e) {
    fmt::print(stderr, "gl_bench: {}\n", e.what());
    return 1;
  }
}
