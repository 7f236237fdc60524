#include "tests/textures/texture_fixtures.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <atomic>
#include <fstream>
#include <mutex>
#include <stdexcept>

#include <unistd.h>

namespace bt::test {

namespace fs = std::filesystem;

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = fs::temp_directory_path() / ("bt_textures_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

namespace {
void putU32(std::vector<uint8_t>& out, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) out[at + i] = static_cast<uint8_t>(v >> (8 * i));
}
void putName(std::vector<uint8_t>& out, size_t at, const std::string& name, size_t field) {
  for (size_t i = 0; i < name.size() && i < field; ++i) out[at + i] = static_cast<uint8_t>(name[i]);
}
} // namespace

std::vector<uint8_t> makeMiptex(const std::string& name, int width, int height, const std::vector<uint8_t>& indices,
                                const std::vector<uint8_t>* ownPalette) {
  const size_t header = 40;
  const size_t mipSizes[4] = {size_t(width) * height, size_t(width / 2) * (height / 2), size_t(width / 4) * (height / 4),
                              size_t(width / 8) * (height / 8)};
  size_t total = header + mipSizes[0] + mipSizes[1] + mipSizes[2] + mipSizes[3];
  if (ownPalette) total += 2 + ownPalette->size();
  std::vector<uint8_t> out(total, 0);
  putName(out, 0, name, 16);
  putU32(out, 16, width);
  putU32(out, 20, height);
  size_t at = header;
  for (int i = 0; i < 4; ++i) {
    putU32(out, 24 + 4 * i, static_cast<uint32_t>(at));
    at += mipSizes[i];
  }
  std::copy(indices.begin(), indices.end(), out.begin() + header);
  if (ownPalette) {
    out[at] = static_cast<uint8_t>(ownPalette->size() / 3);
    out[at + 1] = static_cast<uint8_t>((ownPalette->size() / 3) >> 8);
    std::copy(ownPalette->begin(), ownPalette->end(), out.begin() + at + 2);
  }
  return out;
}

std::vector<uint8_t> makeWad(const std::string& magic, const std::vector<WadLump>& lumps) {
  std::vector<uint8_t> out(12, 0);
  putName(out, 0, magic, 4);
  std::vector<uint32_t> offsets;
  for (const WadLump& lump : lumps) {
    offsets.push_back(static_cast<uint32_t>(out.size()));
    out.insert(out.end(), lump.data.begin(), lump.data.end());
  }
  const size_t directory = out.size();
  out.resize(directory + 32 * lumps.size(), 0);
  putU32(out, 4, static_cast<uint32_t>(lumps.size()));
  putU32(out, 8, static_cast<uint32_t>(directory));
  for (size_t i = 0; i < lumps.size(); ++i) {
    const size_t at = directory + 32 * i;
    putU32(out, at, offsets[i]);
    putU32(out, at + 4, static_cast<uint32_t>(lumps[i].data.size()));
    putU32(out, at + 8, static_cast<uint32_t>(lumps[i].data.size()));
    out[at + 12] = lumps[i].type;
    putName(out, at + 16, lumps[i].name, 16);
  }
  return out;
}

std::vector<uint8_t> makeWal(const std::string& name, int width, int height, const std::vector<uint8_t>& indices) {
  const size_t header = 100;
  std::vector<uint8_t> out(header + indices.size(), 0);
  putName(out, 0, name, 32);
  putU32(out, 32, width);
  putU32(out, 36, height);
  putU32(out, 40, header);
  std::copy(indices.begin(), indices.end(), out.begin() + header);
  return out;
}

void writeFile(const fs::path& path, const std::vector<uint8_t>& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::vector<uint8_t> readFile(const fs::path& path) {
  return readTextureFile(path);
}

Image readWithOpenImageIo(std::span<const uint8_t> bytes, const std::string& name) {
  // IOMemReader only reads, but 2.4 takes a non-const pointer.
  OIIO::Filesystem::IOMemReader proxy(const_cast<uint8_t*>(bytes.data()), bytes.size());
  OIIO::Filesystem::IOProxy* proxyPointer = &proxy;
  std::unique_ptr<OIIO::ImageInput> input;
  {
    // 2.4 reads ICC profiles and Exif blocks through tables not safe to build from two threads.
    static std::mutex openMutex;
    const std::lock_guard lock(openMutex);
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxyPointer); // with a config, 2.4 reads the proxy from it
    input = OIIO::ImageInput::open(name, &config, &proxy);
  }
  if (!input) throw std::runtime_error(name + ": " + OIIO::geterror());
  const OIIO::ImageSpec spec = input->spec();
  const int channels = spec.nchannels;
  std::vector<uint8_t> pixels(size_t(spec.width) * size_t(spec.height) * size_t(channels));
  if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, pixels.data()))
    throw std::runtime_error(name + ": " + input->geterror());
  Image image;
  image.width = spec.width;
  image.height = spec.height;
  image.rgba.resize(size_t(image.width) * size_t(image.height) * 4);
  const int alpha = spec.alpha_channel >= 0 ? spec.alpha_channel : (channels == 2 ? 1 : channels >= 4 ? 3 : -1);
  for (size_t i = 0, n = size_t(image.width) * size_t(image.height); i < n; ++i) {
    const uint8_t* src = &pixels[i * size_t(channels)];
    uint8_t* dst = &image.rgba[i * 4];
    dst[0] = src[0];
    dst[1] = src[channels < 3 ? 0 : 1];
    dst[2] = src[channels < 3 ? 0 : 2];
    dst[3] = alpha >= 0 && alpha < channels ? src[alpha] : 255;
  }
  return image;
}

void writeImage(const fs::path& path, int width, int height, int channels, const std::vector<uint8_t>& pixels) {
  fs::create_directories(path.parent_path());
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) throw std::runtime_error("no image writer for " + path.string());
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
  if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close())
    throw std::runtime_error("cannot write " + path.string() + ": " + out->geterror());
}

Scene makeScene(const fs::path& sourcePath, const std::vector<std::pair<std::string, std::string>>& keys,
                const std::vector<std::string>& materialNames) {
  Scene scene;
  scene.sourcePath = sourcePath.string();
  Entity world;
  world.keys.emplace_back("classname", "worldspawn");
  for (const auto& kv : keys) world.keys.push_back(kv);
  scene.entities.push_back(world);
  for (const std::string& name : materialNames) {
    Material m;
    m.name = name;
    scene.materials.push_back(m);
  }
  return scene;
}

int countWarnings(const Scene& scene) {
  int n = 0;
  for (const Diagnostic& d : scene.diagnostics) n += d.severity == Severity::Warning;
  return n;
}

std::string describe(const Diagnostics& diagnostics) {
  std::string text;
  for (const Diagnostic& d : diagnostics) text += format(d) + "\n";
  return text;
}

} // namespace bt::test

// OpenImageIO 2.4 keeps the text of the last failed ImageInput::open in a thread-local string
// that LeakSanitizer sometimes reports at exit. It is one buffer per thread, not a growing leak,
// and not ours to free.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:OpenImageIO_v2_4::ImageInput::geterror\n";
}
