#include "renderer/image_output.h"

#include "scene/names.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <fmt/chrono.h>
#include <fmt/format.h>
#include <png.h>

#include <array>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

namespace bt {

namespace {

// The EXR's channels, in the order of the interleaved pixels below: the linear beauty as R, G,
// B (the default layer), then the AOVs and, after --denoise, the denoised beauty. OpenEXR stores
// them sorted by name; readers find them by name. The second moment of the samples' luminance
// (moment2.Y, exposure applied squared) is written where the tracer kept it, so that a stored
// image can be denoised again as the tracer's own (the denoiser lab, issue 18).
constexpr std::array<const char*, 13> kExrChannels{"R",        "G",        "B",       "albedo.R",   "albedo.G",   "albedo.B",  "normal.X",
                                                   "normal.Y", "normal.Z", "depth.Z", "denoised.R", "denoised.G", "denoised.B"};
constexpr const char* kExrMoment2 = "moment2.Y";

// Linear beauty (exposure applied) and the AOVs as 32-bit float channels, ZIP-compressed (16
// scanlines a block), the exposure in the header: what OpenImageIO wrote before brushtrace
// dropped it, so that files written by either read the same.
void writeExr(const std::string& temp, const RenderImage& image, const OutputSettings& output) {
  const size_t n = size_t(image.width) * size_t(image.height);
  const bool denoised = !image.denoised.empty(), moment = image.luminanceMoment2.size() == n;
  const size_t channels = (denoised ? 13 : 10) + (moment ? 1 : 0);
  std::vector<float> pixels(n * channels);
  const float exposure = std::exp2(output.exposureEv);
  for (size_t i = 0; i < n; ++i) {
    float* p = &pixels[i * channels];
    const glm::vec3 b = image.beauty[i] * exposure;
    p[0] = b.x, p[1] = b.y, p[2] = b.z;
    p[3] = image.albedo[i].x, p[4] = image.albedo[i].y, p[5] = image.albedo[i].z;
    p[6] = image.normal[i].x, p[7] = image.normal[i].y, p[8] = image.normal[i].z;
    p[9] = image.depth[i];
    if (denoised) {
      const glm::vec3 d = image.denoised[i] * exposure;
      p[10] = d.x, p[11] = d.y, p[12] = d.z;
    }
    if (moment) p[channels - 1] = image.luminanceMoment2[i] * exposure * exposure;
  }
  Imf::Header header(image.width, image.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  header.insert("brushtrace:exposureEV", Imf::FloatAttribute(output.exposureEv));
  header.insert("brushtrace:exposure", Imf::StringAttribute(output.exposureAuto ? "auto" : "given"));
  header.insert("brushtrace:samples", Imf::IntAttribute(image.samples));
  Imf::addCapDate(header, fmt::format("{:%Y:%m:%d %H:%M:%S}", fmt::localtime(std::time(nullptr))));
  Imf::FrameBuffer frame;
  const size_t xStride = channels * sizeof(float), yStride = xStride * size_t(image.width);
  for (size_t c = 0; c < channels; ++c) {
    const char* name = moment && c == channels - 1 ? kExrMoment2 : kExrChannels[c];
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    frame.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(&pixels[c]), xStride, yStride));
  }
  Imf::OutputFile file(temp.c_str(), header);
  file.setFrameBuffer(frame);
  file.writePixels(image.height);
}

// 8-bit RGB through libpng's simplified API (which marks the file sRGB, as the pixels are).
void writePng(const std::string& temp, const RenderImage& image, const OutputSettings& output) {
  const std::vector<uint8_t> pixels = displayPixels(image, output);
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.width);
  png.height = png_uint_32(image.height);
  png.format = PNG_FORMAT_RGB;
  if (!png_image_write_to_file(&png, temp.c_str(), 0, pixels.data(), 0, nullptr)) throw std::runtime_error(png.message);
}

} // namespace

RenderImage readExrImage(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    RenderImage image;
    image.width = window.max.x - window.min.x + 1;
    image.height = window.max.y - window.min.y + 1;
    const size_t n = size_t(image.width) * size_t(image.height);
    constexpr size_t kAovChannels = 10; // kExrChannels without the denoised layer
    for (size_t c = 0; c < kAovChannels; ++c)
      if (!file.header().channels().findChannel(kExrChannels[c]))
        throw std::runtime_error(fmt::format("no channel {} (not an EXR brushtrace wrote)", kExrChannels[c]));
    const bool moment = file.header().channels().findChannel(kExrMoment2) != nullptr;
    const size_t channels = kAovChannels + (moment ? 1 : 0);
    std::vector<float> pixels(n * channels);
    Imf::FrameBuffer frame;
    const size_t xStride = channels * sizeof(float), yStride = xStride * size_t(image.width);
    char* origin = reinterpret_cast<char*>(pixels.data()) -
        (ptrdiff_t(window.min.x) * ptrdiff_t(xStride) + ptrdiff_t(window.min.y) * ptrdiff_t(yStride));
    for (size_t c = 0; c < channels; ++c)
      frame.insert(c < kAovChannels ? kExrChannels[c] : kExrMoment2, Imf::Slice(Imf::FLOAT, origin + c * sizeof(float), xStride, yStride));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    const auto* ev = file.header().findTypedAttribute<Imf::FloatAttribute>("brushtrace:exposureEV");
    const auto* samples = file.header().findTypedAttribute<Imf::IntAttribute>("brushtrace:samples");
    image.samples = samples ? samples->value() : 0;
    const float unexpose = std::exp2(-(ev ? ev->value() : 0.0f));
    for (size_t i = 0; i < n; ++i) {
      const float* p = &pixels[i * channels];
      image.beauty.emplace_back(p[0] * unexpose, p[1] * unexpose, p[2] * unexpose);
      image.albedo.emplace_back(p[3], p[4], p[5]);
      image.normal.emplace_back(p[6], p[7], p[8]);
      image.depth.push_back(p[9]);
      if (moment) image.luminanceMoment2.push_back(p[10] * unexpose * unexpose);
    }
    return image;
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("{}: cannot read image: {}", path, e.what()));
  }
}

void writeImage(const std::string& path, const RenderImage& image, const OutputSettings& output) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const std::string ext = lowercase(target.extension().string());
  if (ext != ".png" && ext != ".exr") throw std::runtime_error(fmt::format("{}: output must be .png or .exr", path));
  // Written under a hidden name beside the target, renamed over it at the end: a reader of the
  // target never sees half an image.
  const fs::path temp = target.parent_path() / fmt::format(".{}.tmp{}{}", target.stem().string(), getpid(), ext);
  try {
    if (ext == ".png")
      writePng(temp.string(), image, output);
    else
      writeExr(temp.string(), image, output);
  } catch (const std::exception& e) {
    std::error_code ec;
    fs::remove(temp, ec);
    throw std::runtime_error(fmt::format("{}: cannot write image: {}", path, e.what()));
  }
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw std::runtime_error(fmt::format("{}: cannot rename the finished image into place: {}", path, ec.message()));
  }
}

} // namespace bt
