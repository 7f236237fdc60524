#include "tests/render/box_scene.h"

#include "tests/support/scene_builder.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <random>

namespace bt::test {

BoxSceneBuilder::BoxSceneBuilder() {
  scene_.sourcePath = "<box scene>";
  scene_.format = "valve220";
  Entity world;
  world.keys = {{"classname", "worldspawn"}};
  scene_.entities.push_back(world);
}

std::string BoxSceneBuilder::material(const std::string& name, uint8_t r, uint8_t g, uint8_t b) {
  Material m;
  m.name = name;
  m.width = m.height = 16;
  m.source = TextureSource::LooseImage;
  m.baseColor.width = m.baseColor.height = 16;
  for (int i = 0; i < 16 * 16; ++i) m.baseColor.rgba.insert(m.baseColor.rgba.end(), {r, g, b, 255});
  scene_.materials.push_back(std::move(m));
  return name;
}

uint32_t BoxSceneBuilder::entity(std::vector<std::pair<std::string, std::string>> keys) {
  Entity e;
  e.keys = std::move(keys);
  e.firstBrush = uint32_t(scene_.brushes.size());
  scene_.entities.push_back(std::move(e));
  return uint32_t(scene_.entities.size() - 1);
}

void BoxSceneBuilder::worldKey(const std::string& key, const std::string& value) {
  scene_.entities[0].keys.emplace_back(key, value);
}

void BoxSceneBuilder::box(glm::dvec3 lo, glm::dvec3 hi, const std::string& texture, uint32_t entity) {
  addBox(scene_, lo, hi, {.material = scene_.findMaterial(texture).value_or(0), .texture = texture, .entity = entity});
  scene_.entities[entity].brushCount++;
}

void BoxSceneBuilder::room(glm::dvec3 lo, glm::dvec3 hi, const std::string& texture, double t) {
  box({lo.x - t, lo.y - t, lo.z - t}, {hi.x + t, hi.y + t, lo.z}, texture); // floor
  box({lo.x - t, lo.y - t, hi.z}, {hi.x + t, hi.y + t, hi.z + t}, texture); // ceiling
  box({lo.x - t, lo.y - t, lo.z}, {lo.x, hi.y + t, hi.z}, texture);         // -x wall
  box({hi.x, lo.y - t, lo.z}, {hi.x + t, hi.y + t, hi.z}, texture);         // +x wall
  box({lo.x, lo.y - t, lo.z}, {hi.x, lo.y, hi.z}, texture);                 // -y wall
  box({lo.x, hi.y, lo.z}, {hi.x, hi.y + t, hi.z}, texture);                 // +y wall
}

// Every kind of light the grid sorts differently: linear (with and without wait and _falloff),
// inverse formulas, spotlights, coloured, soft (_deviance when `soft`), one darklight, one
// local minlight, and a sun seen through a sky patch hung under the ceiling. The lights are
// scattered at random (fixed seed), so the walls shadow most of them from most points.
Scene manyLightsRoom(int count, bool soft, uint32_t seed) {
  BoxSceneBuilder b;
  b.material("white", 200, 200, 200);
  b.material("sky1", 40, 60, 200);
  b.room({-512, -512, 0}, {512, 512, 256}, "white");
  b.box({-16, -512, 0}, {16, 200, 160}, "white");                                                       // half wall
  for (int i = 0; i < 4; ++i) b.box({-400.0 + 200 * i, 250, 0}, {-370.0 + 200 * i, 280, 256}, "white"); // pillars
  b.box({200, -200, 236}, {328, -72, 256}, "sky1"); // sky patch: sunlight reaches what sees it
  b.worldKey("_sunlight", "80");
  b.worldKey("_sun_mangle", "0 -70 0");
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < count; ++i) {
    const glm::vec3 o(-480.0f + 960.0f * u(gen), -480.0f + 960.0f * u(gen), 20.0f + 220.0f * u(gen));
    std::vector<std::pair<std::string, std::string>> keys = {
        {"classname", "light"}, {"origin", fmt::format("{} {} {}", o.x, o.y, o.z)}, {"light", fmt::format("{}", 100.0f + 300.0f * u(gen))}};
    switch (i % 8) {
    case 0: break;                                      // linear
    case 1: keys.push_back({"wait", "2"}); break;       // linear, half reach
    case 2: keys.push_back({"_falloff", "180"}); break; // linear to 0 at 180
    case 3: keys.push_back({"delay", "1"}); break;      // inverse: reaches everywhere
    case 4: keys.push_back({"delay", "5"}); break;      // inverse square "a"
    case 5:
      keys.push_back({"mangle", "30 -60 0"});
      keys.push_back({"angle", "70"});
      break; // spot
    case 6: keys.push_back({"_color", "255 128 64"}); break;
    case 7:
      keys.push_back({"delay", "2"});
      keys.push_back({"wait", "4"});
      break;
    }
    if (soft && i % 3 == 0) keys.push_back({"_deviance", "12"});
    b.entity(keys);
  }
  b.entity({{"classname", "light"}, {"origin", "-300 -300 100"}, {"light", "-150"}});             // darklight
  b.entity({{"classname", "light"}, {"origin", "300 300 100"}, {"light", "40"}, {"delay", "4"}}); // local minlight
  return b.build();
}

Scene manyLightsHall(int count, uint32_t seed) {
  BoxSceneBuilder b;
  b.material("white", 200, 200, 200);
  b.room({-2048, -256, 0}, {2048, 256, 256}, "white");
  for (int wall = 1; wall < 8; ++wall) {
    const double x = -2048.0 + 512.0 * wall;
    b.box({x - 8, -256, 0}, {x + 8, 64, 256}, "white"); // a doorway at y 64 .. 256, z 0 .. 160
    b.box({x - 8, 64, 160}, {x + 8, 256, 256}, "white");
  }
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < count; ++i) {
    const glm::vec3 o(-2030.0f + 4060.0f * u(gen), -240.0f + 480.0f * u(gen), 16.0f + 224.0f * u(gen));
    std::vector<std::pair<std::string, std::string>> keys = {
        {"classname", "light"}, {"origin", fmt::format("{} {} {}", o.x, o.y, o.z)}, {"light", fmt::format("{}", 100.0f + 200.0f * u(gen))}};
    switch (i % 5) {
    case 0: keys.push_back({"wait", fmt::format("{}", 1.0f + 2.0f * u(gen))}); break;
    case 1: keys.push_back({"_falloff", fmt::format("{}", 80.0f + 200.0f * u(gen))}); break;
    case 2:
      keys.push_back({"delay", "2"});
      keys.push_back({"wait", fmt::format("{}", 2.0f + 6.0f * u(gen))});
      break;
    // Physical mode emits (1, 0.627, 0.376) from it, the light this hall had when the light
    // tree's bar was set (LightTree.LessNoisyThanTheNearListsInAHallOfManyLights), before light
    // colours were linearised as the game shows them (physical_light.h colour): "255 160 96",
    // as that hall was written, now emits (1, 0.35, 0.12).
    case 3: keys.push_back({"_color", "255 207.51 165.04"}); break;
    case 4:
      keys.push_back({"mangle", "0 -90 0"});
      keys.push_back({"angle", "60"});
      break;
    }
    b.entity(keys);
  }
  return b.build();
}

Scene lightNearWallRoom() {
  BoxSceneBuilder b;
  b.material("white", 200, 200, 200);
  b.material("grey", 120, 120, 120);
  b.room({-128, -128, 0}, {128, 128, 128}, "white");
  b.box({-20, 20, 0}, {20, 60, 96}, "grey");
  b.entity({{"classname", "light"}, {"origin", "-120 -40 64"}, {"light", "300"}, {"delay", "2"}});
  return b.build();
}

Scene twoSkiesRoom() {
  BoxSceneBuilder b;
  b.material("white", 255, 255, 255);
  b.material("sky_a", 40, 60, 200);
  b.material("sky_b", 200, 60, 40);
  b.box({-272, -144, -16}, {272, 144, 0}, "white");  // floor
  b.box({-272, -144, 0}, {-256, 144, 256}, "white"); // walls
  b.box({256, -144, 0}, {272, 144, 256}, "white");
  b.box({-256, -144, 0}, {256, -128, 256}, "white");
  b.box({-256, 128, 0}, {256, 144, 256}, "white");
  b.box({-272, -144, 256}, {0, 144, 272}, "sky_a"); // the roof
  b.box({0, -144, 256}, {272, 144, 272}, "sky_b");
  b.entity({{"classname", "light"}, {"origin", "0 0 128"}, {"_sun", "1"}, {"mangle", "0 -90 0"}, {"_suntexture", "sky_b"}});
  b.entity({{"classname", "info_intermission"}, {"origin", "0 -100 200"}, {"mangle", "50 90 0"}}); // down onto both halves
  return b.build();
}

Scene waterBesideALight(const char* game, const char* water, std::optional<SurfaceAttributes> surface) {
  BoxSceneBuilder b;
  b.material("floor", 100, 100, 100);
  b.material(water, 100, 100, 100);
  b.box({-512, -512, -16}, {512, 512, 0}, "floor");
  b.box({0, -256, 0}, {256, 256, 128}, water);
  b.worldKey("_bounce", "0");
  b.entity({{"classname", "light"}, {"origin", "-64 0 64"}, {"light", "200"}});
  Scene scene = b.build();
  scene.game = game;
  const Brush& brush = scene.brushes[1];
  for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f) scene.faces[f].surface = surface;
  return scene;
}

Scene furnishedRoom(const FurnishedRoom& options) {
  BoxSceneBuilder b;
  if (options.range) b.worldKey("_range", *options.range);
  b.material("white", 220, 220, 220);
  b.material("red", 200, 40, 30);
  b.material("blue", 40, 60, 190);
  b.room({-128, -128, 0}, {128, 128, 128}, "white");
  b.box({10, -30, 0}, {50, 10, 96}, "red");
  b.box({-128, 40, 0}, {-60, 128, 48}, "blue");
  std::vector<std::pair<std::string, std::string>> light = {
      {"classname", "light"}, {"origin", "-40 -60 110"}, {"light", "300"}, {"delay", "2"}};
  if (options.softLight) light.emplace_back("_deviance", "8");
  b.entity(std::move(light));
  Scene scene = b.build();
  if (options.bricks)
    for (Material& m : scene.materials) {
      m.width = m.height = 32;
      for (int t = 0; t < 16 * 16; ++t)
        if (t % 4 == 0 || (t / 16) % 4 == 0)
          for (int c = 0; c < 3; ++c) m.baseColor.rgba[size_t(t) * 4 + size_t(c)] /= options.tinted ? (c == 2 ? 1 : 3 * (2 - c)) : 6;
    }
  return scene;
}

RenderImage renderFurnishedRoom(const RenderScene& rs, int spp, uint32_t seed, bool lowDiscrepancy) {
  CameraPose pose;
  pose.origin = {-115, -110, 64};
  pose.yaw = 40;
  pose.pitch = 8;
  RenderSettings s;
  s.width = 48;
  s.height = 36;
  s.spp = spp;
  s.seed = seed;
  s.integrator.mode = LightingMode::Physical;
  s.integrator.bounces = 1;
  s.integrator.lowDiscrepancy = lowDiscrepancy;
  return renderCpu(rs, Camera(pose, s.width, s.height), s);
}

} // namespace bt::test
