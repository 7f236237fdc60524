// The compiled lightmaps of a .bsp read and sampled by the tests' own code, independently of the
// importer and the renderer: the oracle of faithful mode (oracle_view_test.cpp) and of the
// compiled view (compiled_view_test.cpp). Each point is sampled bilinearly over the luxels of the
// compiled face that holds it, as GLQuake and QuakeSpasm filter lightmaps, and the cameras those
// tests look from are chosen here.
#pragma once

#include "importers/bsp/bsp_file.h"
#include "quake/bspfile_q2.h"
#include "renderer/camera.h"
#include "lighting/render_scene.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <vector>

namespace bt::test {

// One compiled face of the world model with its lightmap.
struct CompiledFace {
  glm::dvec3 normal{0.0};
  double dist = 0.0;
  std::vector<glm::dvec3> polygon;
  glm::dvec4 vecs[2];
  // World point -> luxel coordinates: luxel (x, y) is centred where dot(p, lm[0].xyz) + lm[0].w
  // == x and likewise y. Quake's grid: vecs / 16 - mins; BSPX LMSHIFT: / (1 << shift); BSPX
  // DECOUPLED_LM: the record's own matrix.
  glm::dvec4 lm[2];
  int mins[2] = {0, 0};
  int width = 0, height = 0;
  size_t offset = 0; // into the lighting lump, in luxels (Quake's grey) or bytes (Half-Life, Quake 2)
  std::array<uint8_t, 4> styles{255, 255, 255, 255};
  double area = 0.0;
};

class LightmapOracle {
public:
  // styleZeroOnly: only faces lit by style 0 alone, style 0 first (what faithful mode bakes);
  // otherwise every lit face with all its styles.
  explicit LightmapOracle(const std::filesystem::path& bspPath, bool styleZeroOnly = true) : bsp_(bsp::readBspFile(bspPath)) {
    rgbLump_ = bsp_.version == bsp::Version::HalfLife30 || bsp_.version == bsp::Version::Quake2_38;
    std::filesystem::path lit = bspPath;
    lit.replace_extension(".lit");
    if (std::ifstream in{lit, std::ios::binary}; in && !rgbLump_) {
      std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (bytes.size() == 8 + 3 * bsp_.lighting.size()) rgb_.assign(bytes.begin() + 8, bytes.end());
    }
    const bsp::Model& world = bsp_.models.at(0);
    for (int32_t fi = world.firstFace; fi < world.firstFace + world.faceCount; ++fi) add(fi, styleZeroOnly);
  }

  const std::vector<CompiledFace>& faces() const { return faces_; }
  const bsp::BspFile& file() const { return bsp_; }

  // The compiled light (stored values, rgb) at world point p of a face facing n, bilinear over the
  // luxels of the compiled face that holds p; nullopt where no lit face lies there.
  std::optional<glm::dvec3> at(const glm::dvec3& p, const glm::dvec3& n) const {
    const std::vector<glm::dvec3> all = allAt(p, n, [this](const CompiledFace& f, int x, int y) { return luxel(f, x, y); });
    if (all.empty()) return std::nullopt;
    return all.front();
  }

  // What `value` gives for the luxels, filtered bilinearly, from every compiled face that holds
  // p (more than one along the seam between two faces).
  using LuxelValue = std::function<glm::dvec3(const CompiledFace&, int x, int y)>;
  std::vector<glm::dvec3> allAt(const glm::dvec3& p, const glm::dvec3& n, const LuxelValue& value) const {
    std::vector<glm::dvec3> out;
    for (const CompiledFace& f : faces_) {
      if (glm::dot(f.normal, n) < 0.999 || std::abs(glm::dot(f.normal, p) - f.dist) > 0.5) continue;
      if (contains(f, p)) out.push_back(bilinear(f, p, value));
    }
    return out;
  }

  // Luxel (x, y) of the face's style number `style` (0 = its first).
  glm::dvec3 luxel(const CompiledFace& f, int x, int y, int style = 0) const {
    const size_t i = size_t(style) * size_t(f.width) * size_t(f.height) + size_t(y) * size_t(f.width) + size_t(x);
    if (rgbLump_) {
      const size_t at = f.offset + 3 * i;
      return {bsp_.lighting[at], bsp_.lighting[at + 1], bsp_.lighting[at + 2]};
    }
    const size_t at = f.offset + i;
    if (!rgb_.empty()) return {rgb_[3 * at], rgb_[3 * at + 1], rgb_[3 * at + 2]};
    return glm::dvec3(bsp_.lighting[at]);
  }
  // The world point of luxel (x, y)'s centre on the face plane.
  glm::dvec3 luxelPoint(const CompiledFace& f, int x, int y) const {
    const glm::dvec3 s(f.lm[0]), t(f.lm[1]);
    const double sv = x - f.lm[0].w, tv = y - f.lm[1].w;
    // Solve dot(p, s) = sv, dot(p, t) = tv, dot(p, n) = dist.
    const glm::dmat3 m = glm::transpose(glm::dmat3(s, t, f.normal));
    return glm::inverse(m) * glm::dvec3(sv, tv, f.dist);
  }

private:
  void add(int32_t fi, bool styleZeroOnly) {
    const bsp::Face& face = bsp_.faces[size_t(fi)];
    if (face.lightOffset < 0 || face.styles[0] == 255) return; // unlit (sky, liquids)
    if (styleZeroOnly && face.styles[0] != 0) return;          // styled only
    const bsp::TexInfo& tex = bsp_.texinfo[size_t(face.texinfo)];
    // Quake 2's ref_gl draws warped (liquid) and sky faces without their lightmap, whatever the
    // compiler stored for them (R_RenderBrushPoly: EmitWaterPolys, the sky box).
    if (bsp_.version == bsp::Version::Quake2_38 && (tex.flags & (quake::q2::SURF_WARP | quake::q2::SURF_SKY))) return;
    CompiledFace f;
    const bsp::BspPlane& plane = bsp_.planes[size_t(face.plane)];
    f.normal = glm::dvec3(plane.normal);
    f.dist = plane.dist;
    if (face.side) f.normal = -f.normal, f.dist = -f.dist;
    f.polygon = bsp_.faceVertices(size_t(fi));
    float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
    for (int a = 0; a < 2; ++a) f.vecs[a] = glm::dvec4(tex.vecs[a][0], tex.vecs[a][1], tex.vecs[a][2], tex.vecs[a][3]);
    for (const glm::dvec3& dv : f.polygon) {
      const glm::vec3 v(dv); // in float, as the engine and the compiler compute extents
      for (int a = 0; a < 2; ++a) {
        const float st = v.x * tex.vecs[a][0] + v.y * tex.vecs[a][1] + v.z * tex.vecs[a][2] + tex.vecs[a][3];
        lo[a] = std::min(lo[a], st), hi[a] = std::max(hi[a], st);
      }
    }
    const float luxel = float(1 << luxelShift(fi));
    for (int a = 0; a < 2; ++a) f.mins[a] = int(std::floor(lo[a] / luxel));
    f.width = int(std::ceil(hi[0] / luxel)) - f.mins[0] + 1;
    f.height = int(std::ceil(hi[1] / luxel)) - f.mins[1] + 1;
    for (int a = 0; a < 2; ++a) f.lm[a] = glm::dvec4(glm::dvec3(f.vecs[a]) / double(luxel), f.vecs[a].w / double(luxel) - f.mins[a]);
    f.offset = size_t(face.lightOffset);
    if (!decoupled(fi, f)) return;
    f.styles = face.styles;
    const size_t styles = size_t(std::count_if(f.styles.begin(), f.styles.end(), [](uint8_t s) { return s != 255; }));
    const size_t luxels = size_t(f.width) * size_t(f.height) * styles;
    if (rgbLump_ ? f.offset + 3 * luxels > bsp_.lighting.size() : f.offset + luxels > bsp_.lighting.size()) return;
    for (size_t i = 1; i + 1 < f.polygon.size(); ++i)
      f.area += 0.5 * glm::length(glm::cross(f.polygon[i] - f.polygon[0], f.polygon[i + 1] - f.polygon[0]));
    faces_.push_back(std::move(f));
  }

  // BSPX LMSHIFT: texels per luxel 1 << shift per face (4, Quake's 16, without the lump).
  int luxelShift(int32_t fi) const {
    const bsp::BspxLump* lump = bsp_.findBspx("LMSHIFT");
    return lump && lump->bytes.size() == bsp_.faces.size() ? lump->bytes[size_t(fi)] : 4;
  }
  // BSPX DECOUPLED_LM: 40 bytes a face, uint16 width and height, int32 offset, float[2][4]
  // world -> luxel matrix (ericw-tools bspx_decoupled_lm_perface). False for a record that is
  // not usable.
  bool decoupled(int32_t fi, CompiledFace& f) const {
    const bsp::BspxLump* lump = bsp_.findBspx("DECOUPLED_LM");
    if (!lump || lump->bytes.size() != bsp_.faces.size() * 40) return true;
    const uint8_t* r = lump->bytes.data() + size_t(fi) * 40;
    uint16_t size[2];
    int32_t offset;
    float m[8];
    std::memcpy(size, r, 4);
    std::memcpy(&offset, r + 4, 4);
    std::memcpy(m, r + 8, 32);
    if (offset < 0) return false;
    f.width = size[0], f.height = size[1];
    f.offset = size_t(offset);
    for (int a = 0; a < 2; ++a) f.lm[a] = glm::dvec4(m[4 * a], m[4 * a + 1], m[4 * a + 2], m[4 * a + 3]);
    return true;
  }

  static bool contains(const CompiledFace& f, const glm::dvec3& p) {
    const auto& w = f.polygon;
    // Quake stores a face's vertices clockwise seen from its front; go by the polygon's own turn.
    glm::dvec3 turn(0.0);
    for (size_t i = 1; i + 1 < w.size(); ++i) turn += glm::cross(w[i] - w[0], w[i + 1] - w[0]);
    const double side = glm::dot(turn, f.normal) < 0.0 ? -1.0 : 1.0;
    for (size_t i = 0; i < w.size(); ++i) {
      const glm::dvec3 edge = w[(i + 1) % w.size()] - w[i];
      const glm::dvec3 inward = side * glm::normalize(glm::cross(f.normal, edge));
      if (glm::dot(p - w[i], inward) < -0.05) return false;
    }
    return true;
  }

  // GLQuake's filter: luxel centres at 16 (mins + x) texels (lm), clamped at the face's border.
  static glm::dvec3 bilinear(const CompiledFace& f, const glm::dvec3& p, const LuxelValue& value) {
    const double u = glm::dot(p, glm::dvec3(f.lm[0])) + f.lm[0].w;
    const double v = glm::dot(p, glm::dvec3(f.lm[1])) + f.lm[1].w;
    const double fu = std::floor(u), fv = std::floor(v);
    const int x0 = std::clamp(int(fu), 0, f.width - 1), x1 = std::clamp(int(fu) + 1, 0, f.width - 1);
    const int y0 = std::clamp(int(fv), 0, f.height - 1), y1 = std::clamp(int(fv) + 1, 0, f.height - 1);
    const double wu = u - fu, wv = v - fv;
    return (value(f, x0, y0) * (1 - wu) + value(f, x1, y0) * wu) * (1 - wv) + (value(f, x0, y1) * (1 - wu) + value(f, x1, y1) * wu) * wv;
  }

  bsp::BspFile bsp_;
  bool rgbLump_ = false;     // Half-Life and Quake 2 store RGB in the lighting lump itself
  std::vector<uint8_t> rgb_; // a Quake .lit's colour, else empty
  std::vector<CompiledFace> faces_;
};

// A camera that looks straight at the centre of a large lit face from in front of it.
inline CameraPose faceCamera(const RenderScene& rs, const CompiledFace& face) {
  glm::dvec3 centre(0.0);
  for (const glm::dvec3& v : face.polygon) centre += v;
  centre /= double(face.polygon.size());
  const glm::vec3 n(face.normal);
  // Back away along the normal, but stay in front of whatever is behind the camera.
  const Ray back{glm::vec3(centre) + n * 0.5f, 0.0f, n, 160.0f};
  const SurfaceHit blocker = traceVisible(rs, back);
  const float distance = blocker.found ? std::max(blocker.t * 0.8f, 4.0f) : 160.0f;
  CameraPose pose;
  pose.origin = glm::vec3(centre) + n * distance;
  const glm::vec3 look = -n;
  pose.yaw = glm::degrees(std::atan2(look.y, look.x));
  pose.pitch = -glm::degrees(std::asin(std::clamp(look.z, -1.0f, 1.0f))); // positive pitch looks down
  pose.source = "face camera";
  return pose;
}

// The default camera, and two that look straight at the two largest lit faces that face apart.
inline std::vector<CameraPose> oracleCameras(const Scene& scene, const RenderScene& rs, const LightmapOracle& oracle) {
  std::vector<CameraPose> cameras{defaultCameraPose(scene)};
  std::vector<const CompiledFace*> largest;
  for (const CompiledFace& f : oracle.faces()) largest.push_back(&f);
  std::sort(largest.begin(), largest.end(), [](auto* a, auto* b) { return a->area > b->area; });
  for (const CompiledFace* f : largest) {
    if (cameras.size() == 3) break;
    if (cameras.size() == 2 && glm::dot(f->normal, largest[0]->normal) > 0.99) continue;
    cameras.push_back(faceCamera(rs, *f));
  }
  return cameras;
}

} // namespace bt::test
