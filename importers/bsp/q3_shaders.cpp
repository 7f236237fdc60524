#include "importers/bsp/q3_shaders.h"

#include "importers/bsp/shader_lexer.h"
#include "scene/names.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace bt::bsp {

namespace {

// One shader's block, read key by key as q3map2's ParseShaderFile reads it, with what the
// engine's R_FindShader takes from it on the way.
class ShaderReader {
public:
  ShaderReader(ShaderLexer& lex, const std::string& script, Diagnostics& diagnostics)
      : lex_(lex), script_(script), diagnostics_(diagnostics) {}

  // The keys of the block whose `{` was just read.
  Quake3Shader read(int line) {
    shader_ = Quake3Shader{};
    light_.defined = true;
    light_.script = script_;
    light_.line = line;
    editorImage_.clear();
    stageImage_.clear();
    stage_ = 0;
    for (int depth = 1; depth > 0;) {
      const std::string_view token = lex_.next();
      if (token.empty()) {
        warn(lex_.line(), "the shader's block ends with the file (a `}` is missing)");
        break;
      }
      if (token == "{" || token == "}") {
        depth += token == "{" ? 1 : -1;
        if (token == "{" && depth == 2) ++stage_;
        continue;
      }
      const std::string keyword = lowercase(token);
      if (depth == 2)
        readStage(keyword);
      else if (depth == 1)
        readKey(keyword);
      lex_.skipArguments();
    }
    shader_.image = !stageImage_.empty() ? stageImage_ : editorImage_;
    return shader_;
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

  // A stage's image and alphaFunc. The engine draws the first stage image it finds (map,
  // clampMap, animMap). q3map2 takes the first of any kind as its light image, but only while the
  // shader names no editor or light image yet (it fills lightImagePath, which stops the search).
  void readStage(const std::string& keyword) {
    if (keyword == "blendfunc") {
      // The first stage is drawn over what lies behind the surface; later stages blend onto it.
      if (stage_ == 1) shader_.blend = readBlendFunc();
      return;
    }
    if (keyword == "alphafunc") {
      const std::string func = lowercase(lex_.next(true));
      if (shader_.alphaTest == AlphaTest::None)
        shader_.alphaTest = func == "gt0" ? AlphaTest::Gt0
            : func == "lt128"             ? AlphaTest::Lt128
            : func == "ge128"             ? AlphaTest::Ge128
                                          : AlphaTest::None;
      return;
    }
    static constexpr std::string_view kMaps[] = {"map", "clampmap", "animmap", "clampanimmap", "mapcomp", "mapnocomp"};
    if (std::find(std::begin(kMaps), std::end(kMaps), keyword) == std::end(kMaps)) return;
    if (keyword.ends_with("animmap")) lex_.next(true); // the frequency
    const std::string_view image = lex_.next(true);
    if (image.empty() || image[0] == '$' || image[0] == '*') return;
    if (stageImage_.empty() && (keyword == "map" || keyword == "clampmap" || keyword == "animmap")) stageImage_ = std::string(image);
    if (editorImage_.empty() && light_.lightImage.empty()) light_.lightImage = std::string(image);
  }

  // ParseStage's blendFunc: a name, or the source and destination factors.
  ShaderBlend readBlendFunc() {
    const std::string src = lowercase(lex_.next(true));
    if (src == "add") return ShaderBlend::Add;
    if (src == "filter") return ShaderBlend::Filter;
    if (src == "blend") return ShaderBlend::Blend;
    const std::string dst = lowercase(lex_.next(true));
    if (dst == "gl_one") return ShaderBlend::Add; // GL_ONE GL_ONE, GL_SRC_ALPHA GL_ONE: behind + image
    if (src == "gl_dst_color" || dst == "gl_src_color") return ShaderBlend::Filter;
    if (dst == "gl_one_minus_src_alpha") return ShaderBlend::Blend; // GL_ONE GL_ONE_MINUS_SRC_ALPHA too
    return ShaderBlend::Opaque;                                     // GL_ONE GL_ZERO, or a blend the preview does not draw
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
      shader_.light.editorImage = editorImage_;
    } else if (keyword == "q3map_lightimage") {
      light_.lightImage = std::string(lex_.next(true));
    } else if (keyword == "skyparms") {
      const std::string base(lex_.next(true));
      shader_.skyBox = base == "-" ? std::string() : base;
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
  Quake3Shader shader_;
  Q3ShaderLight& light_ = shader_.light.light;
  std::string editorImage_, stageImage_;
  int stage_ = 0; // the stage being read, 1 = the first
};

} // namespace

Quake3Shaders parseShaderScript(std::string_view text, const std::string& scriptName, Diagnostics& diagnostics) {
  Quake3Shaders shaders;
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

Quake3Shaders readQuake3Shaders(const GameFiles& files, Diagnostics& diagnostics, std::vector<std::string>* filesRead) {
  Quake3Shaders shaders;
  for (const std::string& script : files.list("scripts", ".shader")) {
    const auto bytes = files.read(script);
    if (!bytes) continue;
    if (filesRead)
      if (const auto holder = files.fileHolding(script)) filesRead->push_back(holder->string());
    const std::string_view text(reinterpret_cast<const char*>(bytes->data()), bytes->size());
    for (auto& [name, shader] : parseShaderScript(text, files.describe(script).value_or(script), diagnostics))
      shaders.try_emplace(name, std::move(shader));
  }
  return shaders;
}

namespace {

// One field of every shader of a script (its warnings dropped).
template <class Field> auto project(std::string_view text, const Field& field) {
  Diagnostics ignored;
  std::map<std::string, std::decay_t<decltype(field(std::declval<const Quake3Shader&>()))>> out;
  for (const auto& [name, shader] : parseShaderScript(text, "", ignored)) out.emplace(name, field(shader));
  return out;
}

} // namespace

std::map<std::string, std::string> parseShaderImages(std::string_view scriptText) {
  auto images = project(scriptText, [](const Quake3Shader& s) { return s.image; });
  std::erase_if(images, [](const auto& entry) { return entry.second.empty(); });
  return images;
}

std::map<std::string, AlphaTest> parseShaderAlphaTests(std::string_view scriptText) {
  return project(scriptText, [](const Quake3Shader& s) { return s.alphaTest; });
}

std::map<std::string, ShaderBlend> parseShaderBlends(std::string_view scriptText) {
  return project(scriptText, [](const Quake3Shader& s) { return s.blend; });
}

std::map<std::string, std::string> parseShaderSkyBoxes(std::string_view scriptText) {
  std::map<std::string, std::string> boxes;
  for (auto& [name, box] : project(scriptText, [](const Quake3Shader& s) { return s.skyBox; }))
    if (box) boxes.emplace(name, *box);
  return boxes;
}

std::map<std::string, ParsedShaderLight> parseShaderLights(std::string_view text, const std::string& scriptName, Diagnostics& diagnostics) {
  std::map<std::string, ParsedShaderLight> lights;
  for (auto& [name, shader] : parseShaderScript(text, scriptName, diagnostics)) lights.emplace(name, std::move(shader.light));
  return lights;
}

} // namespace bt::bsp
