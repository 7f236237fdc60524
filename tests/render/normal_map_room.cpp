#include "tests/render/normal_map_room.h"

#include "importers/import.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <png.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

namespace bt::test {
namespace {

constexpr int kInside = 128; // the room's inside is [-128, 128] x [-128, 128] x [0, 256]
constexpr int kWall = 16;

namespace fs = std::filesystem;

void writeRgb(const fs::path& path, const RgbImage& image) {
  fs::create_directories(path.parent_path());
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.width);
  png.height = png_uint_32(image.height);
  png.format = PNG_FORMAT_RGB;
  if (!png_image_write_to_file(&png, path.c_str(), 0, image.rgb.data(), 0, nullptr))
    throw std::runtime_error("cannot write " + path.string() + ": " + png.message);
}

std::string vec(const glm::ivec3& v) {
  return fmt::format("( {} {} {} )", v.x, v.y, v.z);
}

// One brush side in Valve 220 form: three points clockwise seen from outside (Quake's order: the
// plane's normal is cross(p2 - p0, p1 - p0)), the texture and its axes.
std::string side(const glm::ivec3& normal, const glm::ivec3& point, const std::string& texture, const std::string& axes) {
  const glm::ivec3 along = normal.x != 0 ? glm::ivec3(0, 1, 0) : normal.y != 0 ? glm::ivec3(0, 0, 1) : glm::ivec3(1, 0, 0);
  const glm::ivec3 across = glm::ivec3(glm::cross(glm::vec3(normal), glm::vec3(along)));
  return fmt::format("{} {} {} {} {}\n", vec(point), vec(point + 64 * across), vec(point + 64 * along), texture, axes);
}

// Quake's paraxial texture axes for a side facing `normal`, unrotated at scale 1.
std::string paraxialAxes(const glm::ivec3& normal) {
  if (normal.x != 0) return "[ 0 1 0 0 ] [ 0 0 -1 0 ] 0 1 1";
  if (normal.y != 0) return "[ 1 0 0 0 ] [ 0 0 -1 0 ] 0 1 1";
  return "[ 1 0 0 0 ] [ 0 -1 0 0 ] 0 1 1";
}

// An axial box brush; `inner` replaces the texture and axes of its side facing -x.
std::string box(const glm::ivec3& lo, const glm::ivec3& hi, const std::string& innerSide = {}) {
  std::string text = "{\n";
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1}) {
      glm::ivec3 normal(0);
      normal[axis] = sign;
      const glm::ivec3 point = sign > 0 ? hi : lo;
      if (axis == 0 && sign < 0 && !innerSide.empty())
        text += side(normal, point, "bumpy", innerSide);
      else
        text += side(normal, point, "plain", paraxialAxes(normal));
    }
  return text + "}\n";
}

std::string roomMap(const NormalMapRoomOptions& options) {
  const int in = kInside, out = kInside + kWall, top = 2 * kInside;
  // The bumpy wall's texture: +s to the camera's right (-y), +t down (-z); mirrored, +s to +y.
  const std::string bumpy = options.mirrored ? "[ 0 -1 0 0 ] [ 0 0 -1 0 ] 0 -1 1" : "[ 0 -1 0 0 ] [ 0 0 -1 0 ] 0 1 1";
  std::string map = "// Format: Valve\n{\n\"classname\" \"worldspawn\"\n\"mapversion\" \"220\"\n";
  map += box({in, -out, -kWall}, {out, out, top + kWall}, bumpy); // +x wall
  map += box({-out, -out, -kWall}, {-in, out, top + kWall});      // -x wall
  map += box({-in, in, -kWall}, {in, out, top + kWall});          // +y wall
  map += box({-in, -out, -kWall}, {in, -in, top + kWall});        // -y wall
  map += box({-in, -in, top}, {in, in, top + kWall});             // ceiling
  map += box({-in, -in, -kWall}, {in, in, 0});                    // floor
  map += "}\n";
  map += fmt::format("{{\n\"classname\" \"light\"\n\"origin\" \"{} {} {}\"\n\"light\" \"300\"\n}}\n", options.light.x, options.light.y,
                     options.light.z);
  return map;
}

} // namespace

RgbImage uniformRgb(int width, int height, uint8_t r, uint8_t g, uint8_t b) {
  RgbImage image{width, height, {}};
  for (int i = 0; i < width * height; ++i) image.rgb.insert(image.rgb.end(), {r, g, b});
  return image;
}

RgbImage bumpsNormalMap(int width, int height) {
  RgbImage image{width, height, {}};
  const double twoPi = 6.283185307179586;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const glm::dvec3 n = glm::normalize(glm::dvec3(0.7 * std::sin(twoPi * x / width), 0.5 * std::cos(twoPi * 2.0 * y / height), 1.0));
      for (int c = 0; c < 3; ++c) image.rgb.push_back(uint8_t(std::lround((n[c] + 1.0) * 0.5 * 255.0)));
    }
  return image;
}

NormalMapRoom::Folder::Folder() {
  static std::atomic<int> counter{0};
  path = fs::temp_directory_path() / fmt::format("bt_normal_map_room_{}_{}", ::getpid(), counter++);
  fs::remove_all(path);
  fs::create_directories(path);
}

NormalMapRoom::Folder::~Folder() {
  std::error_code ec;
  fs::remove_all(path, ec);
}

NormalMapRoom::NormalMapRoom(const NormalMapRoomOptions& options) {
  writeRgb(dir_.path / "textures/bumpy.png", uniformRgb(16, 16, 180, 180, 180));
  writeRgb(dir_.path / "textures/plain.png", uniformRgb(16, 16, 120, 120, 120));
  if (!options.normalMap.rgb.empty()) writeRgb(dir_.path / "textures/bumpy_norm.png", options.normalMap);
  if (options.glossy) writeRgb(dir_.path / "textures/bumpy_rough.png", uniformRgb(16, 16, 89, 89, 89));
  const fs::path mapPath = dir_.path / "room.map";
  {
    std::ofstream out(mapPath);
    out << roomMap(options);
    if (!out) throw std::runtime_error("cannot write " + mapPath.string());
  }
  ImportOptions import;
  import.textures.textureDirs.push_back((dir_.path / "textures").string());
  scene_ = importScene(mapPath.string(), import);
  bool found = false;
  for (uint32_t i = 0; i < scene_.faces.size(); ++i)
    if (scene_.faces[i].texture == "bumpy") wallFace_ = i, found = true;
  if (!found) throw std::runtime_error("the normal-map room has no bumpy wall");
  Diagnostics diagnostics;
  render_ = buildRenderScene(scene_, {}, diagnostics);
}

// From the middle of the room, level, towards +x: the bumpy wall fills the view.
CameraPose NormalMapRoom::pose() const {
  return CameraPose{{-8.0f, 0.0f, 128.0f}, 0.0f, 0.0f, 0.0f, "test"};
}

} // namespace bt::test
