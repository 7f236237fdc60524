// brushtrace info MAP [--json]: what a level holds and what the importer could not use.
#include "app/commands.h"
#include "app/usage_checks.h"
#include "importers/models/entity_models.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <utility>

#include <algorithm>

namespace bt::app {

namespace {

// Quake 3 curves, triangle soups and entity models: meshes and their triangles (two faces each, scene.h Mesh).
struct MeshSummary {
  size_t curves = 0, curveTriangles = 0, soups = 0, soupTriangles = 0, models = 0, modelTriangles = 0;
  size_t faces() const { return 2 * (curveTriangles + soupTriangles + modelTriangles); }
};

MeshSummary meshSummary(const Scene& scene) {
  MeshSummary m;
  uint32_t lastModelEntity = ~0u; // a model is one mesh per skin or shader, all of one entity
  for (const Mesh& mesh : scene.meshes) {
    const bool curve = mesh.kind == MeshKind::Curve, model = mesh.kind == MeshKind::Model;
    if (model) m.models += std::exchange(lastModelEntity, mesh.entity) != mesh.entity;
    if (!model) ++(curve ? m.curves : m.soups);
    (curve ? m.curveTriangles : model ? m.modelTriangles : m.soupTriangles) += mesh.faceCount / 2;
  }
  return m;
}

} // namespace

nlohmann::ordered_json infoJson(const Scene& scene) {
  nlohmann::ordered_json textures = nlohmann::ordered_json::array();
  for (const Material& m : scene.materials)
    textures.push_back({{"name", m.name}, {"found", !m.missing()}, {"source", toString(m.source)}, {"path", m.sourcePath}});
  nlohmann::ordered_json problems = nlohmann::ordered_json::array();
  for (const Diagnostic& d : scene.diagnostics)
    if (d.severity != Severity::Note)
      problems.push_back({{"severity", d.severity == Severity::Error ? "error" : "warning"},
                          {"line", d.line},
                          {"column", d.column},
                          {"message", d.message}});
  nlohmann::ordered_json bounds = nullptr;
  if (!scene.bounds.empty())
    bounds = {{"min", {scene.bounds.min.x, scene.bounds.min.y, scene.bounds.min.z}},
              {"max", {scene.bounds.max.x, scene.bounds.max.y, scene.bounds.max.z}}};
  const MeshSummary meshes = meshSummary(scene);
  return {{"path", scene.sourcePath},
          {"dialect", scene.format},
          {"entities", scene.entities.size()},
          {"brushes", scene.brushes.size()},
          {"faces", scene.faces.size() - meshes.faces()},
          {"curves", meshes.curves},
          {"curve_triangles", meshes.curveTriangles},
          {"triangle_soups", meshes.soups},
          {"soup_triangles", meshes.soupTriangles},
          {"models", meshes.models},
          {"model_triangles", meshes.modelTriangles},
          {"bounds", bounds},
          {"textures", textures},
          {"problems", problems}};
}

namespace {

void printInfo(const Scene& scene) {
  const MeshSummary meshes = meshSummary(scene);
  fmt::print("{}\n  dialect   {}\n  entities  {}\n  brushes   {}\n  faces     {}\n", scene.sourcePath, scene.format, scene.entities.size(),
             scene.brushes.size(), scene.faces.size() - meshes.faces());
  if (meshes.curves > 0) fmt::print("  curves    {} ({} triangles)\n", meshes.curves, meshes.curveTriangles);
  if (meshes.soups > 0) fmt::print("  soups     {} ({} triangles)\n", meshes.soups, meshes.soupTriangles);
  if (meshes.models > 0) fmt::print("  models    {} ({} triangles)\n", meshes.models, meshes.modelTriangles);
  if (const Diagnostic* missing = models::missingModelsNote(scene)) fmt::print("  models    {}\n", missing->message);
  if (!scene.bounds.empty())
    fmt::print("  bounds    ({} {} {}) .. ({} {} {})\n", scene.bounds.min.x, scene.bounds.min.y, scene.bounds.min.z, scene.bounds.max.x,
               scene.bounds.max.y, scene.bounds.max.z);
  const auto missing = std::count_if(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.missing(); });
  fmt::print("  textures  {} ({} found, {} missing)\n", scene.materials.size(), scene.materials.size() - missing, missing);
  for (const Material& m : scene.materials)
    fmt::print("    {:<24} {}{}\n", m.name, m.missing() ? "missing" : toString(m.source), m.sourcePath.empty() ? "" : "  " + m.sourcePath);
  size_t problems = 0;
  for (const Diagnostic& d : scene.diagnostics) problems += d.severity != Severity::Note;
  fmt::print("  problems  {}\n", problems);
  for (const Diagnostic& d : scene.diagnostics)
    if (d.severity != Severity::Note) fmt::print("    {}\n", format(d));
}

} // namespace

void addInfoCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand("info", "Summarise a level: dialect, counts, bounds, textures found/missing, invalid brushes");
  struct Args {
    std::string path;
    bool json = false;
    ImportOptions import;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("MAP", args->path,
                  "Level to import (.map, .bsp, ARCHIVE:maps/x.bsp, a level name with a game install), or a .pak/.pk3 to list")
      ->required()
      ->check(levelFile());
  cmd->add_flag("--json", args->json, "Print JSON instead of text");
  addImportOptions(*cmd, args->import);
  cmd->callback([args, &exitCode] {
    exitCode = 0;
    if (printArchiveContents(args->path, args->json)) return;
    const Scene scene = importScene(args->path, args->import);
    if (args->json)
      fmt::print("{}\n", infoJson(scene).dump(1));
    else
      printInfo(scene);
    exitCode = 0;
  });
}

} // namespace bt::app
