// .bsp bytes through what `brushtrace` does with them: readBspFile (every version: BSP29, BSP2,
// 2PSB, BSP30, IBSP 38 and 46), sceneFromBsp (entities, brushes from lumps, BSPX or hull 0,
// frames, compiled lightmaps), then the render preparation.
//
// Input: one selector byte, then the file. Selector bit 0: decode the level's own miptex with a
// palette as importBsp does (a made-up one: which colours does not matter here); bit 1: also
// hand over a .lit file, made from the level's lighting lump and cut short by selector >> 2
// bytes (0 = whole), to reach the .lit reader's size checks.
#include "importers/bsp/bsp_file.h"
#include "importers/bsp/bsp_import.h"
#include "importers/textures/textures.h"
#include "tests/fuzz/fuzz_support.h"

#include <cstdint>
#include <span>

namespace {

bt::Palette rampPalette() {
  bt::Palette p;
  for (size_t i = 0; i < p.rgb.size(); ++i) p.rgb[i] = static_cast<uint8_t>(i / 3);
  return p;
}

// What importBsp's resolver does with the miptex lump, without a game folder to search.
void decodeOwnMiptex(const bt::bsp::BspFile& bsp, bt::Scene& scene) {
  static const bt::Palette palette = rampPalette();
  const bool halfLife = bsp.version == bt::bsp::Version::HalfLife30;
  for (bt::Material& material : scene.materials)
    for (const bt::bsp::Miptex& m : bsp.miptex) {
      if (!m.present || !m.hasPixels || !bt::textureNamesEqual(m.name, material.name)) continue;
      try {
        material = bt::decodeMiptex(m.bytes, &palette, halfLife, "fuzz.bsp (miptex)");
      } catch (const bt::ImportError&) {}
      break;
    }
  bt::loadMaterials(scene, bt::TextureSearch{.load = false});
}

std::vector<uint8_t> litFileFor(const bt::bsp::BspFile& bsp, size_t cut) {
  std::vector<uint8_t> lit = {'Q', 'L', 'I', 'T', 1, 0, 0, 0};
  for (uint8_t v : bsp.lighting) lit.insert(lit.end(), {v, uint8_t(v / 2), uint8_t(255 - v)});
  lit.resize(lit.size() - std::min(cut, lit.size()));
  return lit;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t selector = data[0];
  try {
    const bt::bsp::BspFile bsp = bt::bsp::readBspFile(std::span(data + 1, size - 1), "fuzz.bsp");
    bt::bsp::MaterialResolver resolve;
    if (selector & 1) resolve = [&](bt::Scene& scene) { decodeOwnMiptex(bsp, scene); };
    std::optional<std::vector<uint8_t>> lit;
    if (selector & 2) lit = litFileFor(bsp, selector >> 2);
    const bt::Scene scene = bt::bsp::sceneFromBsp(bsp, resolve, lit);
    bt::fuzz::prepareForRender(scene);
  } catch (const bt::ImportError&) {}
  return 0;
}
