#include "renderer/denoise_fade.h"

namespace bt {

float denoiseShare(int samples) {
  if (samples <= kDenoiseFullUntil) return 1.0f;
  if (samples >= kDenoiseGoneAt) return 0.0f;
  return float(kDenoiseGoneAt - samples) / float(kDenoiseGoneAt - kDenoiseFullUntil);
}

std::vector<glm::vec3> displayedBeauty(const std::vector<glm::vec3>& raw, const std::vector<glm::vec3>& denoised, int samples) {
  const float share = denoiseShare(samples);
  if (share <= 0.0f) return raw;
  std::vector<glm::vec3> out(raw.size());
  for (size_t i = 0; i < raw.size(); ++i) out[i] = share * denoised[i] + (1.0f - share) * raw[i];
  return out;
}

} // namespace bt
