// A small level for normal-map tests, imported the way users load one: a Valve 220 .map and
// loose PNG textures (base colour plus a `_norm` companion) written to a temporary folder, read
// through importScene with that folder as a texture folder (`--textures DIR`). The PNGs are
// written with libpng, not OpenImageIO, so that the GPU check's portable parity tests
// (bt_importers_portable) use the room too.
//
// The room is 256 units on a side. Its +x wall, seen from inside (face normal -x), carries the
// texture "bumpy"; the camera looks at it from the room's middle, so it fills the image. The
// texture axes on that wall are right (-y) and down (-z) as seen from the camera, so with an
// unmirrored texture +s points to -y and up in the image (-t) to +z; `mirrored` gives s a
// negative scale (+s points to +y). One point light lights the room.
#pragma once

#include "renderer/camera.h"
#include "lighting/render_scene.h"
#include "scene/scene.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <vector>

namespace bt::test {

// An 8-bit RGB image, rows top to bottom.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;
};

RgbImage uniformRgb(int width, int height, uint8_t r, uint8_t g, uint8_t b);
// A normal map of smooth bumps, tilting up to ~35 degrees along s and t, every texel different:
// for comparing two tracers' filtering and frames, not for a direction to expect.
RgbImage bumpsNormalMap(int width, int height);

struct NormalMapRoomOptions {
  RgbImage normalMap;    // "bumpy_norm.png"; none when empty
  bool mirrored = false; // the wall's texture with scale -1 along s
  glm::vec3 light{0.0f, 0.0f, 128.0f};
  bool glossy = false; // a "bumpy_rough.png" companion (roughness 0.35), which adds the GGX lobe
};

class NormalMapRoom {
public:
  explicit NormalMapRoom(const NormalMapRoomOptions& options);
  NormalMapRoom(const NormalMapRoom&) = delete;
  NormalMapRoom& operator=(const NormalMapRoom&) = delete;

  const Scene& scene() const { return scene_; }
  const RenderScene& render() const { return render_; }
  CameraPose pose() const;
  uint32_t wallFace() const { return wallFace_; } // index into scene().faces

private:
  // A fresh folder under the system's temporary one, removed with its files.
  struct Folder {
    Folder();
    ~Folder();
    Folder(const Folder&) = delete;
    Folder& operator=(const Folder&) = delete;
    std::filesystem::path path;
  };

  Folder dir_; // the .map and its textures
  Scene scene_;
  RenderScene render_; // points into scene_
  uint32_t wallFace_ = 0;
};

} // namespace bt::test
