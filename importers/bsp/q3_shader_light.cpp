#include "importers/bsp/q3_shader_light.h"

#include "importers/bsp/shader_lexer.h"
#include "importers/textures/textures.h"
#include "scene/names.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>

namespace bt::bsp {

namespace {

// One shader's block, read key by key as ParseShaderFile reads it.
class ShaderReader {
public:
  ShaderReader(ShaderLexer& lex, const std::string& script, Diagnostics& diagnostics)
      : lex_(lex), script_(script), diagnostics_(diagnostics) {}

  // The keys of the block whose `{` was just read.
  ParsedShaderLight read(int line) {
    light_ = Q3ShaderLight{};
    light_.defined = true;
    light_.script = script_;
    light_.line = line;
    editorImage_.clear();
    for (int depth = 1; depth > 0;) {
      const std::string_view token = lex_.next();
      if (token.empty()) {
        warn(lex_.line(), "the shader's block ends with the file (a `}` is missing)");
        break;
      }
      if (token == "{" || token == "}") {
        depth += token == "{" ? 1 : -1;
        continue;
      }
      const std::string keyword = lowercase(token);
      if (depth == 2)
        readStageImage(keyword);
      else if (depth == 1)
        readKey(keyword);
      lex_.skipArguments();
    }
    return {light_, editorImage_};
  }

private:
  void warn(int line, const std::string& message) { diagnostics_.push_back({Severity::Warning, script_, line, 0, message}); }

  // The next argument as atof reads it, warning when it is missing or no number.
  float number(std::string_view keyword) {
    const std::string_view token = lex_.next(true);
    const std::string text(token);
    char* end = nullptr;
    const float value = std::strtof(text.c_str(), &end);
    if (token.empty() || end == text.c_str() || !std::isfinite(value)) {
      warn(lex_.line(), fmt::format("{} expects a number{}", keyword, token.empty() ? "" : fmt::format(", not '{}'", token)));
      return 0.0f;
    }
    return value;
  }

  // Only the stages' images count while the shader names no editor or light image yet, and the
  // first one found is taken (it fills lightImagePath, which stops the search).
  void readStageImage(const std::string& keyword) {
    if (!editorImage_.empty() || !light_.lightImage.empty()) return;
    static constexpr std::string_view kMaps[] = {"map", "clampmap", "animmap", "clampanimmap", "mapcomp", "mapnocomp"};
    if (std::find(std::begin(kMaps), std::end(kMaps), keyword) == std::end(kMaps)) return;
    if (keyword.ends_with("animmap")) lex_.next(true); // the frequency
    const std::string_view image = lex_.next(true);
    if (!image.empty() && image[0] != '$' && image[0] != '*') light_.lightImage = std::string(image);
  }

  void readSun(bool extended) {
    Q3ShaderSun sun;
    for (float& c : sun.color) c = number("q3map_sun");
    sun.intensity = number("q3map_sun");
    sun.degrees = number("q3map_sun");
    sun.elevation = number("q3map_sun");
    if (extended) {
      if (const std::string_view deviance = lex_.next(true); !deviance.empty()) {
        sun.deviance = float(std::atof(std::string(deviance).c_str()));
        sun.samples = std::max(1, std::atoi(std::string(lex_.next(true)).c_str()));
      }
    }
    light_.suns.push_back(sun);
    light_.sky = true; // ApplySurfaceParm("sky")
  }

  void readKey(const std::string& keyword) {
    if (keyword == "surfaceparm") {
      const std::string parm = lowercase(lex_.next(true));
      light_.sky |= parm == "sky";
      light_.nodraw |= parm == "nodraw";
      light_.nolightmap |= parm == "nolightmap";
    } else if (keyword == "qer_editorimage") {
      editorImage_ = std::string(lex_.next(true));
    } else if (keyword == "q3map_lightimage") {
      light_.lightImage = std::string(lex_.next(true));
    } else if (keyword == "skyparms") {
      const std::string base(lex_.next(true));
      if (!base.empty() && base != "-" && lowercase(base) != "full" && light_.lightImage.empty()) light_.lightImage = base + "_up";
    } else if (keyword == "q3map_sun" || keyword == "q3map_sunext" || keyword == "sun") {
      readSun(keyword == "q3map_sunext");
    } else if (keyword == "q3map_skylight") {
      light_.skyLightValue = std::max(number(keyword), 0.0f);
      light_.skyLightIterations = std::max(int(number(keyword)), 2);
    } else if (keyword == "q3map_surfacelight") {
      light_.surfaceLight = number(keyword);
    } else if (keyword == "q3map_lightrgb") {
      float c[3];
      for (float& v : c) v = number(keyword);
      const float peak = std::max({c[0], c[1], c[2]}); // ColorNormalize: black becomes white
      for (int i = 0; i < 3; ++i) light_.color[i] = peak == 0.0f ? 1.0f : c[i] / peak;
      light_.hasLightRGB = true;
    } else if (keyword == "q3map_lightsubdivide") {
      light_.subdivide = float(int(number(keyword))); // atoi
    } else if (keyword == "q3map_backsplash") {
      light_.backsplashFraction = number(keyword) * 0.01f;
      light_.backsplashDistance = number(keyword);
    }
  }

  ShaderLexer& lex_;
  const std::string& script_;
  Diagnostics& diagnostics_;
  Q3ShaderLight light_;
  std::string editorImage_;
};

std::string withoutExtension(std::string_view name) {
  const size_t dot = name.find_last_of('.');
  const size_t slash = name.find_last_of('/');
  if (dot != std::string_view::npos && (slash == std::string_view::npos || dot > slash)) name = name.substr(0, dot);
  return std::string(name);
}

// q3map2's ImageLoad: the image under any of the extensions it reads.
std::optional<Image> loadImage(const GameFiles& files, std::string_view name, Diagnostics& diagnostics,
                               std::vector<std::string>* filesRead) {
  const std::string stem = withoutExtension(name);
  for (const char* ext : {".tga", ".jpg", ".png"}) {
    const std::string file = stem + ext;
    const auto bytes = files.read(file);
    if (!bytes) continue;
    if (filesRead)
      if (const auto holder = files.fileHolding(file)) filesRead->push_back(holder->string());
    try {
      return decodeImage(*bytes, file);
    } catch (const ImportError& e) {
      diagnostics.push_back(
          {Severity::Warning, files.describe(file).value_or(file), 0, 0, "cannot decode the light image: " + e.diagnostic().message});
    }
  }
  return std::nullopt;
}

} // namespace

std::map<std::string, ParsedShaderLight> parseShaderLights(std::string_view text, const std::string& scriptName, Diagnostics& diagnostics) {
  std::map<std::string, ParsedShaderLight> shaders;
  ShaderLexer lex(text);
  ShaderReader reader(lex, scriptName, diagnostics);
  while (true) {
    std::string name(lex.next());
    if (name.empty()) break;
    const int line = lex.line();
    if (name == "{" || name == "}") {
      diagnostics.push_back(
          {Severity::Warning, scriptName, line, 0, fmt::format("a stray '{}' where a shader name belongs; skipped", name)});
      if (name == "{") reader.read(line); // skip the nameless block
      continue;
    }
    if (const size_t suffix = name.find(":q3map"); suffix != std::string::npos) name.resize(suffix);
    const std::string_view open = lex.next();
    if (open != "{") {
      diagnostics.push_back(
          {Severity::Warning, scriptName, lex.line(), 0, fmt::format("shader {}: '{{' expected after its name, found '{}'", name, open)});
      continue;
    }
    shaders.try_emplace(lowercase(name), reader.read(line));
  }
  return shaders;
}

void setColorFromImage(Q3ShaderLight& light, const Image& image) {
  double sum[3] = {0.0, 0.0, 0.0};
  for (size_t i = 0; i + 3 < image.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) sum[c] += image.rgba[i + c];
  const double peak = std::max({sum[0], sum[1], sum[2]});
  for (int c = 0; c < 3; ++c) light.color[c] = peak == 0.0 ? 1.0f : float(sum[c] / peak);
}

void readQuake3ShaderLight(std::vector<Material>& materials, const GameFiles& files, Diagnostics& diagnostics,
                           std::vector<std::string>* filesRead) {
  std::map<std::string, ParsedShaderLight> shaders;
  for (const std::string& script : files.list("scripts", ".shader")) {
    const auto bytes = files.read(script);
    if (!bytes) continue;
    if (filesRead)
      if (const auto holder = files.fileHolding(script)) filesRead->push_back(holder->string());
    const std::string_view text(reinterpret_cast<const char*>(bytes->data()), bytes->size());
    for (auto& [name, shader] : parseShaderLights(text, files.describe(script).value_or(script), diagnostics))
      shaders.try_emplace(name, std::move(shader));
  }
  for (Material& m : materials) {
    // A .bsp names the shader; a .map leaves out the "textures/" that q3map2 puts before it.
    auto it = shaders.find(lowercase(withoutExtension(m.name)));
    if (it == shaders.end()) it = shaders.find("textures/" + lowercase(withoutExtension(m.name)));
    if (it == shaders.end()) continue;
    m.q3 = it->second.light;
    // si->color lights surface lights and sky lights only; the images are read for those alone.
    if (m.q3.hasLightRGB || (m.q3.surfaceLight <= 0.0f && m.q3.skyLightValue <= 0.0f)) continue;
    for (const std::string& image : {m.q3.lightImage, it->second.editorImage, it->first}) {
      if (image.empty()) continue;
      if (const auto loaded = loadImage(files, image, diagnostics, filesRead)) {
        setColorFromImage(m.q3, *loaded);
        break;
      }
    }
  }
}

} // namespace bt::bsp
