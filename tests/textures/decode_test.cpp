// Decoding: palettes, Quake/Half-Life miptex, Quake 2 .wal, WAD directories, malformed input.
#include "importers/game/archive.h"
#include "importers/textures/textures.h"
#include "tests/test_data.h"
#include "tests/textures/texture_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <random>
#include <thread>

namespace bt {
namespace {

namespace fs = std::filesystem;
using test::makeMiptex;
using test::makeWad;

// A palette whose entry i is (i, 255 - i, i / 2): every index decodes to a distinct colour.
Palette rampPalette() {
  Palette p;
  for (int i = 0; i < 256; ++i) {
    p.rgb[i * 3] = static_cast<uint8_t>(i);
    p.rgb[i * 3 + 1] = static_cast<uint8_t>(255 - i);
    p.rgb[i * 3 + 2] = static_cast<uint8_t>(i / 2);
  }
  return p;
}

void expectTexel(const Image& image, int x, int y, int r, int g, int b, int a) {
  const uint8_t* t = image.texel(x, y);
  EXPECT_EQ(t[0], r) << "at " << x << "," << y;
  EXPECT_EQ(t[1], g) << "at " << x << "," << y;
  EXPECT_EQ(t[2], b) << "at " << x << "," << y;
  EXPECT_EQ(t[3], a) << "at " << x << "," << y;
}

void expectPaletteTexel(const Image& image, int x, int y, const Palette& p, int index) {
  expectTexel(image, x, y, p.rgb[index * 3], p.rgb[index * 3 + 1], p.rgb[index * 3 + 2], 255);
}

std::vector<uint8_t> indicesOf(int width, int height, auto indexAt) {
  std::vector<uint8_t> v(static_cast<size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) v[static_cast<size_t>(y) * width + x] = static_cast<uint8_t>(indexAt(x, y));
  return v;
}

int countNonBlack(const Image& image) {
  int n = 0;
  for (size_t i = 0; i < image.rgba.size(); i += 4) n += image.rgba[i] || image.rgba[i + 1] || image.rgba[i + 2];
  return n;
}

TEST(Palette, LoadsTheQuakePaletteAndRejectsOtherSizes) {
  BT_REQUIRE_SHARED(shared);
  const Palette quake = loadPalette(shared / "maps/palettes/quake.lmp");
  // Facts of Quake's palette: index 0 is black, 255 the '{' key colour, 251 white (fullbright).
  EXPECT_EQ(quake.rgb[0] + quake.rgb[1] + quake.rgb[2], 0);
  EXPECT_EQ(quake.rgb[255 * 3], 159);
  EXPECT_EQ(quake.rgb[255 * 3 + 1], 91);
  EXPECT_EQ(quake.rgb[255 * 3 + 2], 83);
  EXPECT_EQ(quake.rgb[254 * 3], 255);

  test::TempDir dir;
  test::writeFile(dir / "short.lmp", std::vector<uint8_t>(767, 1));
  try {
    loadPalette(dir / "short.lmp");
    FAIL() << "a 767-byte palette was accepted";
  } catch (const ImportError& e) {
    EXPECT_NE(std::string(e.what()).find("short.lmp"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("767"), std::string::npos) << e.what();
  }
  EXPECT_THROW(loadPalette(dir / "does_not_exist.lmp"), ImportError);
}

TEST(Palette, ReadsTheQuake2PaletteFromTheEndOfAPcxFile) {
  const Palette ramp = rampPalette();
  std::vector<uint8_t> pcx(128 + 40, 0);
  pcx[0] = 0x0A; // PCX manufacturer byte
  pcx.push_back(0x0C);
  pcx.insert(pcx.end(), ramp.rgb.begin(), ramp.rgb.end());
  const Palette read = paletteFromBytes(pcx, "colormap.pcx");
  EXPECT_EQ(read.rgb, ramp.rgb);
}

TEST(Miptex, DecodesQuakeTexelsThroughThePalette) {
  const Palette p = rampPalette();
  const auto indices = indicesOf(16, 8, [](int x, int y) { return (x + 16 * y) % 200; });
  const Material m = decodeMiptex(makeMiptex("wall", 16, 8, indices), &p, false, "test");
  EXPECT_EQ(m.name, "wall");
  EXPECT_EQ(m.width, 16);
  EXPECT_EQ(m.height, 8);
  EXPECT_EQ(m.source, TextureSource::Miptex);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) expectPaletteTexel(m.baseColor, x, y, p, (x + 16 * y) % 200);
  EXPECT_TRUE(m.emissive.empty()) << "no index >= 224, so no fullbright texel";
}

TEST(Miptex, QuakeFullbrightIndicesBecomeEmissive) {
  const Palette p = rampPalette();
  // Left half index 100 (lit normally), right half 230 (fullbright); one texel 255.
  auto indices = indicesOf(16, 16, [](int x, int) { return x < 8 ? 100 : 230; });
  indices[15] = 255;
  const Material m = decodeMiptex(makeMiptex("light1", 16, 16, indices), &p, false, "test");
  ASSERT_FALSE(m.emissive.empty());
  ASSERT_EQ(m.emissive.width, 16);
  expectTexel(m.emissive, 0, 3, 0, 0, 0, 255);
  expectPaletteTexel(m.emissive, 8, 3, p, 230);
  expectPaletteTexel(m.emissive, 15, 0, p, 255); // 255 is fullbright outside '{' textures
  expectPaletteTexel(m.baseColor, 8, 3, p, 230); // and still the base colour
  expectPaletteTexel(m.baseColor, 15, 0, p, 255);
  EXPECT_EQ(countNonBlack(m.emissive), 8 * 16);
}

TEST(Miptex, Index255IsTransparentInFenceTexturesOnly) {
  const Palette p = rampPalette();
  const auto indices = indicesOf(16, 16, [](int x, int y) { return (x + y) % 2 ? 255 : 17; });
  const Material fence = decodeMiptex(makeMiptex("{grate", 16, 16, indices), &p, false, "test");
  expectTexel(fence.baseColor, 1, 0, 0, 0, 0, 0);
  expectPaletteTexel(fence.baseColor, 0, 0, p, 17);
  EXPECT_TRUE(fence.emissive.empty()) << "the transparent index is not a fullbright";

  const Material plain = decodeMiptex(makeMiptex("grate", 16, 16, indices), &p, false, "test");
  expectPaletteTexel(plain.baseColor, 1, 0, p, 255);
}

TEST(Miptex, HalfLifeUsesItsOwnPaletteAndHasNoFullbrights) {
  std::vector<uint8_t> own(768);
  for (int i = 0; i < 256; ++i) own[i * 3] = own[i * 3 + 1] = own[i * 3 + 2] = static_cast<uint8_t>(255 - i);
  const auto indices = indicesOf(16, 16, [](int x, int) { return x < 4 ? 255 : x < 8 ? 230 : 3; });
  const Material m = decodeMiptex(makeMiptex("{fence", 16, 16, indices, &own), nullptr, true, "test");
  expectTexel(m.baseColor, 0, 0, 0, 0, 0, 0);         // index 255 of a '{' texture: transparent
  expectTexel(m.baseColor, 5, 0, 25, 25, 25, 255);    // own palette entry 230
  expectTexel(m.baseColor, 9, 9, 252, 252, 252, 255); // own palette entry 3
  EXPECT_TRUE(m.emissive.empty());
}

TEST(Miptex, TruncatedOrBadHeadersThrowNamingTheTexture) {
  const Palette p = rampPalette();
  const std::vector<uint8_t> full = makeMiptex("brick", 16, 16, std::vector<uint8_t>(256, 7));
  const size_t pixelsEnd = 40 + 256;
  for (size_t size = 0; size < pixelsEnd; ++size) {
    const std::span<const uint8_t> cut(full.data(), size);
    try {
      decodeMiptex(cut, &p, false, "walls.wad:brick");
      FAIL() << "accepted a miptex cut at " << size << " bytes";
    } catch (const ImportError& e) {
      EXPECT_EQ(e.diagnostic().file, "walls.wad:brick");
    }
  }
  EXPECT_NO_THROW(decodeMiptex(std::span(full.data(), pixelsEnd), &p, false, "brick"));

  std::vector<uint8_t> zeroWidth = full;
  zeroWidth[16] = zeroWidth[17] = 0;
  EXPECT_THROW(decodeMiptex(zeroWidth, &p, false, "x"), ImportError);
  std::vector<uint8_t> huge = full;
  huge[19] = 0x7f; // width 2^30 + 16
  EXPECT_THROW(decodeMiptex(huge, &p, false, "x"), ImportError);
  std::vector<uint8_t> external = full;
  std::fill(external.begin() + 24, external.begin() + 40, 0);
  EXPECT_THROW(decodeMiptex(external, &p, false, "x"), ImportError);
  EXPECT_THROW(decodeMiptex(full, nullptr, false, "x"), ImportError) << "Quake miptex without a palette";
  // Half-Life miptex without room for its palette.
  EXPECT_THROW(decodeMiptex(full, nullptr, true, "x"), ImportError);
}

TEST(Wal, DecodesQuake2TexturesWithIndex255Transparent) {
  const Palette p = rampPalette();
  const auto indices = indicesOf(8, 4, [](int x, int) { return x == 0 ? 255 : x * 10; });
  const Material m = decodeWal(test::makeWal("e1u1/test", 8, 4, indices), p, "test.wal");
  EXPECT_EQ(m.name, "e1u1/test");
  EXPECT_EQ(m.source, TextureSource::Wal);
  expectTexel(m.baseColor, 0, 2, 0, 0, 0, 0);
  expectPaletteTexel(m.baseColor, 3, 2, p, 30);
  const std::vector<uint8_t> wal = test::makeWal("t", 8, 4, indices);
  for (size_t size : {0, 50, 99, 100, 131}) EXPECT_THROW(decodeWal(std::span(wal.data(), size), p, "t.wal"), ImportError) << size;
}

TEST(Wal, DecodesTheEricwToolsAlphamaskWal) {
  BT_REQUIRE_SHARED(shared);
  const Palette q2 = loadPalette(shared / "maps/palettes/quake2.lmp");
  const fs::path file = shared / "maps/ericw-tools/testmaps/q2_wal_metadata/textures/e1u1/alphamask.wal";
  const Material m = decodeWal(test::readFile(file), q2, file.string());
  EXPECT_EQ(m.name, "watertest"); // the name stored inside the file
  ASSERT_EQ(m.width, 64);
  ASSERT_EQ(m.height, 64);
  // The file holds 2768 texels of index 5 and 1328 of index 255 (transparent).
  int transparent = 0, grey = 0;
  for (size_t i = 0; i < m.baseColor.rgba.size(); i += 4) {
    const uint8_t* t = &m.baseColor.rgba[i];
    transparent += t[3] == 0;
    grey += t[3] == 255 && t[0] == q2.rgb[15] && t[1] == q2.rgb[16] && t[2] == q2.rgb[17];
  }
  EXPECT_EQ(transparent, 1328);
  EXPECT_EQ(grey, 2768);
}

TEST(WadFile, ReadsLibreQuakesDevWad) {
  BT_REQUIRE_SHARED(shared);
  const Palette quake = loadPalette(shared / "maps/palettes/quake.lmp");
  const WadFile wad = WadFile::open(shared / "maps/librequake/texture-wads/lq_dev_legacy/lq_dev_legacy.wad");
  EXPECT_FALSE(wad.halfLife());
  EXPECT_EQ(wad.entries().size(), 396u);
  EXPECT_NE(wad.findTexture("CLIP"), nullptr) << "names are case-insensitive";
  EXPECT_NE(wad.findTexture("*Water1"), nullptr);
  EXPECT_EQ(wad.findTexture("clip_"), nullptr);
  EXPECT_FALSE(wad.palette()) << "this WAD carries no palette lump";

  const std::optional<Material> clip = wad.loadTexture("Clip", &quake);
  ASSERT_TRUE(clip);
  EXPECT_EQ(clip->name, "Clip") << "the material keeps the name it was asked for";
  EXPECT_EQ(clip->source, TextureSource::Wad2);
  EXPECT_EQ(clip->sourcePath, wad.displayName());
  EXPECT_EQ(clip->width, 64);
  expectPaletteTexel(clip->baseColor, 0, 0, quake, 72); // its first texel is index 72
  EXPECT_TRUE(clip->emissive.empty());

  // char_0 (16x16) uses fullbright indices in 120 of its texels.
  const std::optional<Material> digit = wad.loadTexture("char_0", &quake);
  ASSERT_TRUE(digit);
  EXPECT_EQ(digit->width, 16);
  EXPECT_EQ(countNonBlack(digit->emissive), 120);
  EXPECT_FALSE(wad.loadTexture("no_such_texture", &quake));
}

// LibreQuake's PNG folders hold the same textures as its WAD for these names: decoding the WAD
// with the palette must give exactly the colours OpenImageIO reads from the PNGs.
TEST(WadFile, WadTexturesMatchLibreQuakesPngsOfTheSameName) {
  BT_REQUIRE_SHARED(shared);
  const fs::path lq = shared / "maps/librequake/texture-wads";
  const Palette quake = loadPalette(shared / "maps/palettes/quake.lmp");
  const WadFile wad = WadFile::open(lq / "lq_dev_legacy/lq_dev_legacy.wad");
  for (const char* name : {"clip", "origin", "skip", "trigger", "*blood1", "*slime1", "*smile", "*teleport", "*water1", "*water2"}) {
    SCOPED_TRACE(name);
    const std::optional<Material> fromWad = wad.loadTexture(name, &quake);
    ASSERT_TRUE(fromWad);
    std::string file = name;
    if (file[0] == '*') file = "star_" + file.substr(1);
    const Image png = loadImage(lq / "lq_dev" / (file + ".png"));
    ASSERT_EQ(png.width, fromWad->width);
    ASSERT_EQ(png.height, fromWad->height);
    EXPECT_EQ(png.rgba, fromWad->baseColor.rgba);
  }
}

// The importer decodes loose images on all cores. OpenImageIO 2.4 parses a PNG's ICC profile
// (LibreQuake's PNGs carry one) with state that is not safe to share between threads
// (OpenImageIO issue 3756): concurrent opens hung or corrupted the heap. Many threads open the
// same files at once here, first thing in the process, and each must read exactly what one
// thread alone reads afterwards.
// brushtrace reads loose images without OpenImageIO (issue 21) and must give the texels it gave
// with it: every fourth PNG of the shared maps and every fourth TGA and JPEG of OpenArena's
// pak0.pk3 (Debian's openarena-085-data, when installed), read as the importers read them.
TEST(LooseImage, TexelsAreTheOnesOpenImageIoRead) {
  BT_REQUIRE_SHARED(shared);
  std::vector<std::pair<std::string, std::vector<uint8_t>>> files; // name, bytes
  std::vector<fs::path> pngs;
  for (const auto& e : fs::recursive_directory_iterator(shared / "maps"))
    if (e.path().extension() == ".png") pngs.push_back(e.path());
  std::sort(pngs.begin(), pngs.end());
  for (size_t i = 0; i < pngs.size(); i += 4) files.emplace_back(pngs[i].string(), readTextureFile(pngs[i]));
  const size_t fromShared = files.size();
  if (const auto pk3 = game::openArchive("/usr/share/games/openarena/baseoa/pak0.pk3")) {
    size_t seen = 0;
    for (const std::string& name : pk3->names()) {
      const std::string ext = fs::path(name).extension().string();
      if ((ext == ".tga" || ext == ".jpg") && seen++ % 4 == 0) files.emplace_back(name, *pk3->read(name));
    }
  }
  ASSERT_GT(fromShared, 300u);
  size_t differ = 0;
  for (const auto& [name, bytes] : files) {
    const Image ours = name.starts_with("/") ? loadImage(name) : decodeImage(bytes, name);
    const Image reference = test::readWithOpenImageIo(bytes, name);
    const bool same = ours.width == reference.width && ours.height == reference.height && ours.rgba == reference.rgba;
    differ += !same;
    EXPECT_TRUE(same) << name << ": " << ours.width << "x" << ours.height << " against OpenImageIO's " << reference.width << "x"
                      << reference.height;
    if (differ > 5) break;
  }
  std::cout << files.size() << " images (" << fromShared << " from the shared maps) read as OpenImageIO read them\n";
}

TEST(LooseImage, ManyThreadsDecodeTheSameImagesAsOne) {
  BT_REQUIRE_SHARED(shared);
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(shared / "maps/librequake/texture-wads/lq_dev"))
    if (entry.path().extension() == ".png") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  files.resize(std::min<size_t>(files.size(), 48));
  ASSERT_GE(files.size(), 16u);
  // The threads go first: the state OpenImageIO shared is made on first use.
  constexpr int kThreads = 8;
  std::vector<std::vector<Image>> together(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      for (size_t i = 0; i < files.size(); ++i) together[t].push_back(loadImage(files[(i + size_t(t) * 5) % files.size()]));
    });
  for (std::thread& t : threads) t.join();
  std::vector<Image> alone;
  for (const fs::path& f : files) alone.push_back(loadImage(f));
  for (int t = 0; t < kThreads; ++t)
    for (size_t i = 0; i < files.size(); ++i) {
      const Image& expected = alone[(i + size_t(t) * 5) % files.size()];
      EXPECT_EQ(together[t][i].width, expected.width);
      EXPECT_EQ(together[t][i].rgba, expected.rgba) << files[(i + size_t(t) * 5) % files.size()];
    }
}

TEST(WadFile, ReadsHalfLifeWad3WithPerTexturePalettes) {
  BT_REQUIRE_SHARED(shared);
  const Palette quake = loadPalette(shared / "maps/palettes/quake.lmp");
  const WadFile wad = WadFile::open(shared / "maps/ericw-tools/testmaps/deprecated/hlwad.wad");
  EXPECT_TRUE(wad.halfLife());
  const std::optional<Material> m = wad.loadTexture("HLTEST", nullptr);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->source, TextureSource::Wad3);
  EXPECT_EQ(m->width, 64);
  // Its first texel is index 190, which its own palette maps to (124,124,190); Quake's differs.
  expectTexel(m->baseColor, 0, 0, 124, 124, 190, 255);
  EXPECT_NE(quake.rgb[190 * 3 + 2], 190);
  EXPECT_TRUE(wad.loadTexture("!liquidtest", nullptr));
}

// TrenchBroom's malformed WAD fixtures: each a clear error, never a crash.
TEST(WadFile, MalformedTrenchBroomFixtures) {
  BT_REQUIRE_SHARED(shared);
  const fs::path dir = shared / "maps/trenchbroom/lib/TbFsLib/test/fixture/fs/Wad";
  const auto errorOf = [&](const char* file) -> std::string {
    try {
      WadFile::open(dir / file);
    } catch (const ImportError& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
      return e.diagnostic().message;
    }
    return "";
  };
  EXPECT_NE(errorOf("bad_magic.wad").find("magic 'WAD9'"), std::string::npos);
  EXPECT_NE(errorOf("too_small.wad").find("too small"), std::string::npos);
  EXPECT_NE(errorOf("directory_out_of_bounds.wad").find("directory"), std::string::npos);
  EXPECT_NE(errorOf("entry_count_too_large.wad").find("directory"), std::string::npos);
  EXPECT_NE(errorOf("entry_out_of_bounds.wad").find("'toofar'"), std::string::npos);

  const WadFile empty = WadFile::open(dir / "wad3_empty.wad");
  EXPECT_TRUE(empty.halfLife());
  EXPECT_TRUE(empty.entries().empty());

  const WadFile skips = WadFile::open(dir / "skips_empty_entry_name.wad");
  ASSERT_EQ(skips.entries().size(), 1u);
  EXPECT_EQ(skips.entries()[0].name, "real");
  // "real" holds the 5 bytes "hello": found, but not a miptex.
  const Palette p = rampPalette();
  EXPECT_THROW(skips.loadTexture("real", &p), ImportError);
}

// Every prefix of real WADs and random byte damage to their headers and directories: each open
// or decode either succeeds or throws ImportError (ASan/UBSan check the rest).
TEST(WadFile, TruncatedAndDamagedWadsNeverCrash) {
  BT_REQUIRE_SHARED(shared);
  const Palette p = rampPalette();
  const fs::path testmaps = shared / "maps/ericw-tools/testmaps";
  std::mt19937 random(12345);
  int errors = 0, loaded = 0;
  for (const char* file : {"deprecated/fence.wad", "deprecated/hlwad.wad", "deprecated/hintskip.wad"}) {
    const std::vector<uint8_t> original = test::readFile(testmaps / file);
    const auto tryAll = [&](std::vector<uint8_t> bytes) {
      try {
        const WadFile wad = WadFile::fromBytes(std::move(bytes), file);
        for (const WadFile::Entry& e : wad.entries()) {
          try {
            loaded += wad.loadTexture(e.name, &p).has_value();
          } catch (const ImportError&) {
            ++errors;
          }
        }
      } catch (const ImportError&) {
        ++errors;
      }
    };
    for (size_t size = 0; size < original.size(); size += 97)
      tryAll(std::vector<uint8_t>(original.begin(), original.begin() + static_cast<ptrdiff_t>(size)));
    const uint32_t directory = original[8] | original[9] << 8 | original[10] << 16 | original[11] << 24;
    for (int round = 0; round < 200; ++round) {
      std::vector<uint8_t> damaged = original;
      for (int flip = 0; flip < 3; ++flip) {
        // Header, directory, or a miptex header (the first lump starts at 12).
        const size_t region = random() % 3;
        const size_t at = region == 0 ? random() % 12
            : region == 1             ? directory + random() % (damaged.size() - directory)
                                      : 12 + random() % 40;
        damaged[at] = static_cast<uint8_t>(random());
      }
      tryAll(std::move(damaged));
    }
  }
  EXPECT_GT(errors, 0);
  EXPECT_GT(loaded, 0);
}

TEST(Placeholder, IsACheckerOfTwoGreysIn8x8Cells) {
  const Image c = checkerPlaceholder(64, 32);
  ASSERT_EQ(c.width, 64);
  ASSERT_EQ(c.height, 32);
  const uint8_t a = c.texel(0, 0)[0], b = c.texel(8, 0)[0];
  EXPECT_NE(a, b);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      const uint8_t* t = c.texel(x, y);
      EXPECT_EQ(t[0], ((x / 8 + y / 8) % 2) ? b : a);
      EXPECT_EQ(t[0], t[1]);
      EXPECT_EQ(t[1], t[2]);
      EXPECT_EQ(t[3], 255);
    }
}

// Found by tests/fuzz/fuzz_bsp: a miptex header of 40 bytes naming a 16384x16384 texture with
// no pixels made a placeholder of a GB (several such names: the machine's memory).
TEST(Placeholder, AboveTwoToTheTenthASideItIsDrawnSmallerByAWholeFactor) {
  EXPECT_EQ(checkerPlaceholder(1024, 512).width, 1024);
  const Image huge = checkerPlaceholder(16384, 16384);
  EXPECT_EQ(huge.width, 1024);
  EXPECT_EQ(huge.height, 1024);
  const Image wide = checkerPlaceholder(3000, 100); // factor 3, rounded up: 1000 x 34
  EXPECT_EQ(wide.width, 1000);
  EXPECT_EQ(wide.height, 34);
  EXPECT_EQ(wide.rgba, checkerPlaceholder(1000, 34).rgba);
}

} // namespace
} // namespace bt
