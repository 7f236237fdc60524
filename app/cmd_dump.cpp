// brushtrace dump MAP [--json]: the imported scene, face by face.
#include "app/commands.h"
#include "app/usage_checks.h"
#include "app/scene_json.h"

#include <fmt/format.h>

#include <cstdio>

namespace bt::app {

namespace {
nlohmann::ordered_json vec(const dvec3& v) {
  return nlohmann::ordered_json::array({v.x, v.y, v.z});
}
} // namespace

nlohmann::ordered_json dumpJson(const Scene& scene) {
  nlohmann::ordered_json entities = nlohmann::ordered_json::array();
  for (const Entity& e : scene.entities) {
    nlohmann::ordered_json keys = nlohmann::ordered_json::array();
    for (const auto& [k, v] : e.keys) keys.push_back(nlohmann::ordered_json::array({k, v}));
    nlohmann::ordered_json brushes = nlohmann::ordered_json::array();
    for (uint32_t b = e.firstBrush; b < e.firstBrush + e.brushCount; ++b) {
      const Brush& brush = scene.brushes[b];
      nlohmann::ordered_json faces = nlohmann::ordered_json::array();
      for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f) {
        const Face& face = scene.faces[f];
        nlohmann::ordered_json winding = nlohmann::ordered_json::array();
        for (const dvec3& p : face.winding) winding.push_back(vec(p));
        faces.push_back({{"line", face.line},
                         {"texture", face.texture},
                         {"normal", vec(face.plane.normal)},
                         {"dist", face.plane.dist},
                         {"origin", vec(face.frame.origin)},
                         {"tangent", vec(face.frame.tangent)},
                         {"bitangent", vec(face.frame.bitangent)},
                         {"winding", std::move(winding)}});
      }
      brushes.push_back({{"line", brush.line}, {"faces", std::move(faces)}});
    }
    entities.push_back(
        {{"classname", std::string(e.classname())}, {"line", e.line}, {"keys", std::move(keys)}, {"brushes", std::move(brushes)}});
  }
  return {{"dialect", scene.format}, {"entities", std::move(entities)}};
}

void addDumpCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand("dump", "Print the imported scene (entities, brushes, faces with planes, windings, texture frames)");
  struct Args {
    std::string path;
    bool json = false;
    ImportOptions import;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("MAP", args->path, "Level to import (.map, .bsp, ARCHIVE:maps/x.bsp, or a level name with --game/--basedir)")
      ->required()
      ->check(levelFile());
  cmd->add_flag("--json", args->json, "Print JSON (the only format, also without this flag)");
  addImportOptions(*cmd, args->import);
  cmd->callback([args, &exitCode] {
    // Geometry only unless asked: dump prints no pixels, so it does not need to read textures.
    Scene scene = importScene(args->path, args->import);
    fmt::print("{}\n", dumpJson(scene).dump(1));
    for (const Diagnostic& d : scene.diagnostics)
      if (d.severity != Severity::Note) fmt::print(stderr, "{}\n", format(d));
    exitCode = 0;
  });
}

} // namespace bt::app
