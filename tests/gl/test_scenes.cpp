#include "tests/gl/test_scenes.h"

#include "scene/winding.h"
#include "scene/color.h"

#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>

namespace bt::test {

namespace {

double srgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// Bilinear filtering with repeat on the stored 8-bit values, texel centres at (i + 0.5), then
// sRGB decoding: what the CPU reference computes.
glm::dvec3 sampleBilinearRepeat(const Image& image, double u, double v) {
  const double x = u * image.width - 0.5, y = v * image.height - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const double wx = x - fx, wy = y - fy;
  auto texel = [&](double tx, double ty) {
    const int ix = static_cast<int>(((static_cast<long long>(tx) % image.width) + image.width) % image.width);
    const int iy = static_cast<int>(((static_cast<long long>(ty) % image.height) + image.height) % image.height);
    const uint8_t* t = image.texel(ix, iy);
    return glm::dvec3(t[0], t[1], t[2]) / 255.0;
  };
  const glm::dvec3 c = glm::mix(glm::mix(texel(fx, fy), texel(fx + 1, fy), wx), glm::mix(texel(fx, fy + 1), texel(fx + 1, fy + 1), wx), wy);
  return {srgbToLinear(c.x), srgbToLinear(c.y), srgbToLinear(c.z)};
}

Image makeImage(int w, int h, const std::vector<std::array<uint8_t, 3>>& colours) {
  Image image;
  image.width = w;
  image.height = h;
  for (int i = 0; i < w * h; ++i) {
    const auto& c = colours[static_cast<size_t>(i) % colours.size()];
    image.rgba.insert(image.rgba.end(), {c[0], c[1], c[2], 255});
  }
  return image;
}

} // namespace

void addBrush(Scene& scene, const std::vector<Plane>& planes, const Bounds& bounds, uint32_t material) {
  // The GL scenes' windings were clipped from smaller squares than the builder's default.
  addBrush(scene, planes, {.material = material, .texture = scene.materials[material].name}, {.radius = 65536.0, .epsilon = 1e-6}, bounds);
}

void addBox(Scene& scene, dvec3 min, dvec3 max, uint32_t material) {
  addBrush(scene,
           {{{1, 0, 0}, max.x}, {{-1, 0, 0}, -min.x}, {{0, 1, 0}, max.y}, {{0, -1, 0}, -min.y}, {{0, 0, 1}, max.z}, {{0, 0, -1}, -min.z}},
           Bounds{min, max}, material);
}

Scene makeTestRoom() {
  Scene scene;
  Material checker;
  checker.name = "checker";
  checker.source = TextureSource::LooseImage;
  checker.baseColor = makeImage(4, 4, {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}, {40, 80, 120}});
  Material stripes;
  stripes.name = "stripes";
  stripes.width = 32;
  stripes.height = 16;
  stripes.source = TextureSource::LooseImage;
  stripes.baseColor = makeImage(2, 1, {{200, 180, 20}, {10, 30, 90}});
  Material plain;
  plain.name = "plain";
  scene.materials = {checker, stripes, plain};

  addBox(scene, {-272, -272, -16}, {272, 272, 0}, 0);   // floor
  addBox(scene, {-272, -272, 256}, {272, 272, 272}, 1); // ceiling
  addBox(scene, {-272, -272, 0}, {-256, 272, 256}, 1);  // walls
  addBox(scene, {256, -272, 0}, {272, 272, 256}, 0);
  addBox(scene, {-256, -272, 0}, {256, -256, 256}, 0);
  addBox(scene, {-256, 256, 0}, {256, 272, 256}, 2);
  addBox(scene, {40, -60, 0}, {104, 4, 200}, 1); // pillar
  // A wedge: a box cut by a plane sloping down towards the camera, so one face is not axial.
  const dvec3 slope = glm::normalize(dvec3(-1, -0.3, 1));
  addBrush(scene,
           {{{1, 0, 0}, 200},
            {{-1, 0, 0}, -120},
            {{0, 1, 0}, 160},
            {{0, -1, 0}, -80},
            {{0, 0, -1}, 0},
            {slope, glm::dot(slope, dvec3(200, 160, 90))}},
           Bounds{{120, 80, 0}, {200, 160, 90}}, 0);
  return scene;
}

gl::CameraBasis testCamera(int width, int height) {
  gl::CameraBasis c;
  c.origin = {-200, -150, 120};
  const glm::vec3 target{100, 60, 40};
  c.forward = glm::normalize(target - c.origin);
  const glm::vec3 right = glm::normalize(glm::cross(c.forward, glm::vec3(0, 0, 1)));
  const glm::vec3 up = glm::cross(right, c.forward);
  const float tanHalfX = 1.0f; // 90 degrees horizontally, as Quake's default fov
  c.right = right * tanHalfX;
  c.up = up * (tanHalfX * static_cast<float>(height) / static_cast<float>(width));
  return c;
}

Scene makeManyTextureSizesWall() {
  Scene scene;
  const int widths[] = {4, 8, 12, 16, 24, 32};
  const int heights[] = {4, 8, 16, 20};
  for (int row = 0; row < 4; ++row)
    for (int column = 0; column < 6; ++column) {
      Material m;
      m.name = "size" + std::to_string(widths[column]) + "x" + std::to_string(heights[row]);
      m.source = TextureSource::LooseImage;
      m.width = widths[column];
      m.height = heights[row];
      m.baseColor.width = m.width;
      m.baseColor.height = m.height;
      // A colour per texel from a hash of its place and the material: a texel read from the
      // wrong place (wrapped at another size, or from another layer) shows.
      for (uint32_t i = 0; i < uint32_t(m.width * m.height); ++i) {
        const uint32_t h = (i + 1) * 2654435761u ^ uint32_t(scene.materials.size() + 1) * 40503u;
        m.baseColor.rgba.insert(m.baseColor.rgba.end(), {uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), 255});
      }
      const uint32_t material = uint32_t(scene.materials.size());
      scene.materials.push_back(std::move(m));
      // Side by side without gaps, so that no box's grazing side face is in view.
      const double y = -144 + 48 * column, z = 96 - 48 * (row + 1);
      addBox(scene, {0, y, z}, {16, y + 48, z + 48}, material);
    }
  return scene;
}

gl::CameraBasis manyTextureSizesCamera(int width, int height) {
  gl::CameraBasis c;
  c.origin = {-150, 0, 0};
  c.forward = {1, 0, 0};
  c.right = {0, -1, 0};
  c.up = {0, 0, float(height) / float(width)};
  return c;
}

gl::TextureMode textureModeUnderTest() {
  const char* env = std::getenv("BT_GL_TEXTURES");
  if (!env || !*env) return gl::TextureMode::Auto;
  const auto mode = gl::parseTextureMode(env);
  if (!mode) throw std::invalid_argument(std::string("BT_GL_TEXTURES=") + env + " is not bindless, arrays or auto");
  return *mode;
}

gl::GlContext& sharedGlContext() {
  static const std::unique_ptr<gl::GlContext> context = gl::GlContext::createHeadless();
  context->makeCurrent();
  return *context;
}

gl::AovImages referenceAovs(const Scene& scene, const gl::CameraBasis& camera, int width, int height) {
  gl::AovImages out;
  out.width = width;
  out.height = height;
  const size_t n = static_cast<size_t>(width) * height;
  out.albedo.assign(n, glm::vec4(0.0f));
  out.normal.assign(n, glm::vec3(0.0f));
  out.depth.assign(n, std::numeric_limits<float>::infinity());
  out.face.assign(n, gl::AovImages::kNothingHit);
  const dvec3 origin(camera.origin), forward(camera.forward), right(camera.right), up(camera.up);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double nx = (x + 0.5) / width * 2 - 1, ny = (y + 0.5) / height * 2 - 1;
      const dvec3 dir = glm::normalize(forward + nx * right - ny * up);
      double best = std::numeric_limits<double>::infinity();
      constexpr uint32_t kNone = 0xffffffffu;
      uint32_t bestFace = kNone;
      for (const Brush& b : scene.brushes) {
        double enter = -std::numeric_limits<double>::infinity(), leave = best;
        uint32_t face = kNone;
        bool miss = false;
        for (uint32_t i = b.firstFace; i < b.firstFace + b.faceCount && !miss; ++i) {
          const Plane& p = scene.faces[i].plane;
          const double dist = p.distanceTo(origin), denom = glm::dot(p.normal, dir);
          if (denom < 0) {
            if (-dist / denom > enter) enter = -dist / denom, face = i;
          } else if (denom > 0) {
            leave = std::min(leave, -dist / denom);
          } else if (dist > 0) {
            miss = true;
          }
          miss = miss || enter > leave;
        }
        if (!miss && face != kNone && enter >= 0 && enter < best) best = enter, bestFace = face;
      }
      if (bestFace == kNone) continue;
      const size_t i = static_cast<size_t>(y) * width + x;
      const Face& f = scene.faces[bestFace];
      const Material& m = scene.materials[f.material];
      const dvec3 p = origin + dir * best;
      glm::dvec3 albedo(srgbToLinear(0.5)); // the untextured placeholder: grey 0.5, sRGB-encoded
      if (!m.baseColor.empty()) albedo = sampleBilinearRepeat(m.baseColor, f.frame.s(p) / m.width, f.frame.t(p) / m.height);
      out.albedo[i] = glm::vec4(glm::vec3(albedo), 1.0f);
      out.normal[i] = glm::vec3(f.plane.normal);
      out.depth[i] = static_cast<float>(best);
      out.face[i] = bestFace + 1;
    }
  return out;
}

} // namespace bt::test
