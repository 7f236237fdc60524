#include "renderer/denoise_fade.h"

namespace bt {

float denoiseShare(int samples, const DenoiseFade& fade) {
  if (samples <= fade.fullUntil) return 1.0f;
  if (samples >= fade.goneAt) return 0.0f;
  return float(fade.goneAt - samples) / float(fade.goneAt - fade.fullUntil);
}

std::vector<glm::vec3> displayedBeauty(const std::vector<glm::vec3>& raw, const std::vector<glm::vec3>& denoised, int samples,
                                       const DenoiseFade& fade) {
  const float share = denoiseShare(samples, fade);
  if (share <= 0.0f) return raw;
  std::vector<glm::vec3> out(raw.size());
  for (size_t i = 0; i < raw.size(); ++i) out[i] = share * denoised[i] + (1.0f - share) * raw[i];
  return out;
}

} // namespace bt
