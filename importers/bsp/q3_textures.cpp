#include "importers/bsp/q3_textures.h"
#include "importers/bsp/shader_lexer.h"
#include "importers/textures/textures.h"
#include "scene/names.h"

#include <fmt/format.h>

#include <cctype>
#include <filesystem>

namespace bt::bsp {

namespace {

bool isImage(std::string_view path) {
  return !path.empty() && path[0] != '$' && path[0] != '*';
}

std::string stripExtension(const std::string& name) {
  const size_t dot = name.find_last_of('.');
  const size_t slash = name.find_last_of('/');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) return name.substr(0, dot);
  return name;
}

} // namespace

std::map<std::string, std::string> parseShaderImages(std::string_view scriptText) {
  std::map<std::string, std::string> images;
  ShaderLexer lex(scriptText);
  while (true) {
    const std::string_view name = lex.next();
    if (name.empty()) break;
    if (name == "{" || name == "}") continue; // stray brace: resynchronise
    if (lex.next() != "{") continue;
    std::string stageImage, editorImage;
    int depth = 1;
    while (depth > 0) {
      const std::string_view token = lex.next();
      if (token.empty()) break;
      if (token == "{") {
        ++depth;
      } else if (token == "}") {
        --depth;
      } else {
        const std::string keyword = lowercase(token);
        if (depth == 1 && keyword == "qer_editorimage") {
          editorImage = std::string(lex.next(true));
        } else if (depth == 2 && stageImage.empty() && (keyword == "map" || keyword == "clampmap")) {
          const std::string_view path = lex.next(true);
          if (isImage(path)) stageImage = std::string(path);
        } else if (depth == 2 && stageImage.empty() && keyword == "animmap") {
          lex.next(true); // frequency
          const std::string_view path = lex.next(true);
          if (isImage(path)) stageImage = std::string(path);
        }
        lex.skipArguments();
      }
    }
    const std::string& image = !stageImage.empty() ? stageImage : editorImage;
    if (!image.empty()) images.try_emplace(lowercase(name), image);
  }
  return images;
}

std::map<std::string, AlphaTest> parseShaderAlphaTests(std::string_view scriptText) {
  std::map<std::string, AlphaTest> tests;
  ShaderLexer lex(scriptText);
  while (true) {
    const std::string_view name = lex.next();
    if (name.empty()) break;
    if (name == "{" || name == "}") continue; // stray brace: resynchronise
    if (lex.next() != "{") continue;
    AlphaTest test = AlphaTest::None;
    for (int depth = 1; depth > 0;) {
      const std::string_view token = lex.next();
      if (token.empty()) break;
      if (token == "{") {
        ++depth;
      } else if (token == "}") {
        --depth;
      } else {
        // The first stage's alphaFunc decides what the depth buffer keeps; later ones blend over it.
        if (depth == 2 && test == AlphaTest::None && lowercase(token) == "alphafunc") {
          const std::string func = lowercase(lex.next(true));
          test = func == "gt0" ? AlphaTest::Gt0 : func == "lt128" ? AlphaTest::Lt128 : func == "ge128" ? AlphaTest::Ge128 : test;
        }
        lex.skipArguments();
      }
    }
    tests.try_emplace(lowercase(name), test);
  }
  return tests;
}

void resolveQuake3Materials(std::vector<Material>& materials, const GameFiles& files, Diagnostics& diagnostics,
                            std::vector<std::string>* filesRead) {
  auto noteRead = [&](std::string_view name) {
    if (!filesRead) return;
    if (const auto file = files.fileHolding(name)) filesRead->push_back(file->string());
  };
  std::map<std::string, std::string> shaderImages;
  std::map<std::string, AlphaTest> alphaTests;
  for (const std::string& script : files.list("scripts", ".shader")) {
    const auto bytes = files.read(script);
    if (!bytes) continue;
    noteRead(script);
    const std::string_view text(reinterpret_cast<const char*>(bytes->data()), bytes->size());
    for (auto& [name, image] : parseShaderImages(text)) shaderImages.try_emplace(name, image);
    for (auto& [name, test] : parseShaderAlphaTests(text)) alphaTests.try_emplace(name, test);
  }
  for (Material& m : materials) {
    // Quake 3 draws an image's alpha only where the shader says how.
    const auto test = alphaTests.find(lowercase(m.name));
    m.alphaTest = test != alphaTests.end() ? test->second : AlphaTest::None;
    std::vector<std::string> candidates;
    if (auto it = shaderImages.find(lowercase(m.name)); it != shaderImages.end()) candidates.push_back(stripExtension(it->second));
    candidates.push_back(stripExtension(m.name));
    for (const std::string& base : candidates) {
      for (const char* ext : {".tga", ".jpg", ".png"}) {
        const std::string file = base + ext;
        const auto bytes = files.read(file);
        if (!bytes) continue;
        noteRead(file);
        Image image;
        try {
          image = decodeImage(*bytes, file);
        } catch (const ImportError& e) {
          diagnostics.push_back(
              {Severity::Warning, file, 0, 0, "cannot decode image for shader " + m.name + ": " + e.diagnostic().message});
          continue;
        }
        m.width = image.width;
        m.height = image.height;
        m.baseColor = std::move(image);
        m.source = TextureSource::LooseImage;
        m.sourcePath = file;
        break;
      }
      if (!m.missing()) break;
    }
  }
}

} // namespace bt::bsp
