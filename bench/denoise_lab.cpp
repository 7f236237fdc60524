// denoise_lab DIR [SPP...] [analyze] [shares] [worst N]: the denoiser lab (issue 18). Reads what `gl_bench ... converge 4096
// dump DIR` or `brushtrace bench --time-to-converged --dump DIR` wrote (reference.exr and
// NNNNspp.exr, each with its AOVs and second moment), denoises each step again with today's
// renderer/denoise.h and prints the step's relative MSE raw, denoised and displayed (the viewer's
// fade, renderer/denoise_fade.h) against the reference, as the bench does, and where the worst 1 %
// of the displayed image's error lies: sky, dark pixels, silhouettes, texel edges, fireflies
// (`analyze`; `worst N` lists the N worst pixels of the denoised image), and `shares`: the error
// of blends w x denoised + (1 - w) x raw, from which the fade was chosen.
// So the filter can be tuned on the GPU's images without the GPU.
#include "renderer/denoise.h"
#include "renderer/denoise_fade.h"
#include "renderer/exposure.h"
#include "renderer/image_output.h"
#include "renderer/time_to_converged.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using bt::RenderImage;

double pixelError(const glm::vec3& x, const glm::vec3& r) {
  double sum = 0.0;
  for (int c = 0; c < 3; ++c) sum += double(x[c] - r[c]) * double(x[c] - r[c]) / (double(r[c]) * double(r[c]) + 0.01);
  return sum;
}

float displayLuminance(const glm::vec3& c) {
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

// What kind of pixel i is, for the breakdown of the worst 1 % (the first kind that applies).
const char* kindOf(const RenderImage& image, const std::vector<glm::vec3>& shown, const std::vector<glm::vec3>& reference, size_t i) {
  const int w = image.width, h = image.height, x = int(i % size_t(w)), y = int(i / size_t(w));
  if (!std::isfinite(image.depth[i])) return "nothing hit (sky)";
  const float r = displayLuminance(reference[i]), s = displayLuminance(shown[i]);
  bool silhouette = false, texelEdge = false, crease = false;
  for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
    const int qx = x + dx, qy = y + dy;
    if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
    const size_t q = size_t(qy) * size_t(w) + size_t(qx);
    if (!std::isfinite(image.depth[q]) || std::abs(image.depth[q] - image.depth[i]) > 0.05f * image.depth[i]) silhouette = true;
    if (glm::dot(image.normal[q], image.normal[i]) < 0.9f) crease = true;
    const float a = displayLuminance(image.albedo[i]), b = displayLuminance(image.albedo[q]);
    if (std::abs(a - b) > 0.25f * std::max(a, b)) texelEdge = true;
  }
  if (s > 3.0f * r + 0.05f) return "far brighter than the reference (firefly)";
  if (silhouette) return "silhouette (depth jump)";
  if (crease) return "crease (normal change)";
  if (r < 0.1f) return "dark (reference display < 0.1)";
  if (texelEdge) return "texel edge (albedo change)";
  if (r > 0.9f) return "bright (reference display > 0.9)";
  return "other";
}

void breakdown(const RenderImage& image, const std::vector<glm::vec3>& shown, const std::vector<glm::vec3>& reference) {
  std::vector<std::pair<double, size_t>> errors(reference.size());
  double total = 0.0;
  for (size_t i = 0; i < reference.size(); ++i) total += (errors[i] = {pixelError(shown[i], reference[i]), i}).first;
  const size_t worst = std::max<size_t>(1, errors.size() / 100);
  std::nth_element(errors.begin(), errors.begin() + std::ptrdiff_t(worst), errors.end(), std::greater<>());
  std::vector<std::pair<std::string, std::pair<double, int>>> kinds;
  for (size_t k = 0; k < worst; ++k) {
    const std::string kind = kindOf(image, shown, reference, errors[k].second);
    auto it = std::find_if(kinds.begin(), kinds.end(), [&](const auto& e) { return e.first == kind; });
    if (it == kinds.end()) it = kinds.insert(kinds.end(), {kind, {0.0, 0}});
    it->second.first += errors[k].first, it->second.second += 1;
  }
  std::sort(kinds.begin(), kinds.end(), [](const auto& a, const auto& b) { return a.second.first > b.second.first; });
  for (const auto& [kind, e] : kinds)
    fmt::print("      {:5.1f} % of all the error, {:5} pixels: {}\n", 100.0 * e.first / total, e.second, kind);
  // The error by the reference's displayed luminance, every pixel.
  const float bands[] = {0.02f, 0.05f, 0.1f, 0.2f, 0.5f, 2.0f};
  double lower = 0.0;
  std::string line = "      by reference display luminance:";
  for (float band : bands) {
    double e = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < reference.size(); ++i) {
      const double r = displayLuminance(reference[i]);
      if (r >= lower && r < band) e += pixelError(shown[i], reference[i]), ++n;
    }
    line += fmt::format(" <{}: {:.0f} % ({:.0f} % px)", band, 100.0 * e / total, 100.0 * double(n) / double(reference.size()));
    lower = band;
  }
  fmt::print("{}\n", line);
}

// The n worst pixels of the denoised image, with what the filter saw there.
void listWorst(const RenderImage& image, const RenderImage& reference, const std::vector<glm::vec3>& raw,
               const std::vector<glm::vec3>& filtered, const std::vector<glm::vec3>& referenceDisplay, int n) {
  std::vector<std::pair<double, size_t>> e(referenceDisplay.size());
  for (size_t i = 0; i < e.size(); ++i) e[i] = {pixelError(filtered[i], referenceDisplay[i]), i};
  std::sort(e.begin(), e.end(), std::greater<>());
  for (int k = 0; k < n && k < int(e.size()); ++k) {
    const size_t i = e[size_t(k)].second;
    const float moment2 = image.luminanceMoment2.size() > i ? image.luminanceMoment2[i] : NAN;
    fmt::print("      ({},{}) err {:.2f} ref {:.3f} raw {:.3f} den {:.3f} albedo {:.3f} {:.3f} {:.3f} depth {:.0f} lin raw {:.4f} "
               "ref {:.4f} m2 {:.4g}\n",
               i % size_t(image.width), i / size_t(image.width), e[size_t(k)].first, displayLuminance(referenceDisplay[i]),
               displayLuminance(raw[i]), displayLuminance(filtered[i]), image.albedo[i].x, image.albedo[i].y, image.albedo[i].z,
               image.depth[i], displayLuminance(image.beauty[i]), displayLuminance(reference.beauty[i]), moment2);
  }
}

} // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    fmt::print(stderr, "usage: denoise_lab DIR [SPP...] [analyze] [shares] [worst N]\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::vector<int> spps;
  bool analyze = false, shares = false;
  int worstPixels = 0;
  for (int a = 2; a < argc; ++a) {
    if (std::string(argv[a]) == "analyze")
      analyze = true;
    else if (std::string(argv[a]) == "shares")
      shares = true;
    else if (std::string(argv[a]) == "worst" && a + 1 < argc)
      analyze = true, worstPixels = std::atoi(argv[++a]);
    else
      spps.push_back(std::atoi(argv[a]));
  }
  if (spps.empty())
    for (const int spp : bt::convergeSteps(4096))
      if (std::filesystem::exists(dir / fmt::format("{:04}spp.exr", spp))) spps.push_back(spp);
  const RenderImage reference = bt::readExrImage((dir / "reference.exr").string());
  const float referenceEv = bt::autoExposureEv(reference.beauty, reference.width, reference.height);
  const std::vector<glm::vec3> referenceDisplay = bt::displayedImage(reference.beauty, referenceEv);
  fmt::print("reference {}x{}, exposure {:+.2f} EV\n", reference.width, reference.height, referenceEv);
  for (int spp : spps) {
    RenderImage image = bt::readExrImage((dir / fmt::format("{:04}spp.exr", spp)).string());
    if (image.samples == 0) image.samples = spp;
    const float ev = bt::autoExposureEv(image.beauty, image.width, image.height);
    const auto start = std::chrono::steady_clock::now();
    const std::vector<glm::vec3> denoised = bt::denoise(image);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::vector<glm::vec3> raw = bt::displayedImage(image.beauty, ev), filtered = bt::displayedImage(denoised, ev);
    const std::vector<glm::vec3> shown = bt::displayedImage(bt::displayedBeauty(image.beauty, denoised, image.samples), ev);
    fmt::print("{:5} spp: raw {:.4f} ({:.0f} %), denoised {:.4f} ({:.0f} %), displayed ({:.0f} % denoised) {:.4f} ({:.0f} %); "
               "exposure {:+.2f} EV, denoiser {:.2f} s\n",
               spp, bt::relativeMse(raw, referenceDisplay), 100.0 * bt::worstPercentShare(raw, referenceDisplay),
               bt::relativeMse(filtered, referenceDisplay), 100.0 * bt::worstPercentShare(filtered, referenceDisplay),
               100.0 * bt::denoiseShare(image.samples), bt::relativeMse(shown, referenceDisplay),
               100.0 * bt::worstPercentShare(shown, referenceDisplay), ev, seconds);
    if (shares) {
      std::string line = "      shares:";
      for (float share : {1.0f, 0.9f, 0.8f, 0.7f, 0.6f, 0.5f, 0.4f, 0.3f}) {
        std::vector<glm::vec3> mix(denoised.size());
        for (size_t i = 0; i < mix.size(); ++i) mix[i] = share * denoised[i] + (1.0f - share) * image.beauty[i];
        line += fmt::format(" {:.1f}: {:.4f}", share, bt::relativeMse(bt::displayedImage(mix, ev), referenceDisplay));
      }
      fmt::print("{}\n", line);
    }
    if (analyze) {
      fmt::print("    raw, the worst 1 %:\n");
      breakdown(image, raw, referenceDisplay);
      fmt::print("    denoised, the worst 1 %:\n");
      breakdown(image, filtered, referenceDisplay);
      listWorst(image, reference, raw, filtered, referenceDisplay, worstPixels);
    }
  }
  return 0;
}
