#include "importers/map/map_parser.h"
#include "quake/entity_keys.h"

#include <fmt/format.h>

#include <array>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

namespace bt::map {

namespace {

// A hand-written scanner over the whole file held in memory: the tokenizer is where a large map
// spends its parse time, so it touches each byte once and allocates only for names and keys.
class Scanner {
public:
  Scanner(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  bool atEnd() const { return pos_ >= text_.size(); }
  char peekChar() const { return atEnd() ? '\0' : text_[pos_]; }
  int line() const { return line_; }
  int column() const { return static_cast<int>(pos_ - lineStart_) + 1; }
  size_t position() const { return pos_; }

  [[noreturn]] void fail(const std::string& message) const { failAt(line_, column(), message); }
  [[noreturn]] void failAt(int line, int column, const std::string& message) const {
    throw ImportError(Diagnostic{Severity::Error, path_, line, column, message});
  }

  // Skips spaces, newlines and comments: `//` (every editor) and `;` (QuArK) to the end of the line.
  void skipSpaceAndComments() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        newline();
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        ++pos_;
      } else if (c == ';' || (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/')) {
        skipToEndOfLine();
      } else {
        return;
      }
    }
  }

  // Skips spaces on the current line only; stops at a newline, a comment or a token.
  void skipSpaceOnLine() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v')
        ++pos_;
      else
        return;
    }
  }

  bool atLineEnd() const { return atEnd() || text_[pos_] == '\n'; }
  bool atComment() const {
    return !atEnd() && (text_[pos_] == ';' || (text_[pos_] == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/'));
  }

  // The rest of the line from here, without the newline (used for trailing comments).
  std::string_view restOfLine() {
    const size_t start = pos_;
    skipToEndOfLine();
    std::string_view s = text_.substr(start, pos_ - start);
    while (!s.empty() && s.back() == '\r') s.remove_suffix(1);
    return s;
  }

  void expect(char c, const char* what) {
    skipSpaceAndComments();
    if (atEnd()) fail(fmt::format("unexpected end of file, expected '{}' {}", c, what));
    if (text_[pos_] != c) fail(fmt::format("expected '{}' {}, found {}", c, what, describeHere()));
    ++pos_;
  }

  // A number token: everything up to whitespace or a bracket must be a valid number.
  double number(const char* what) {
    skipSpaceAndComments();
    if (atEnd()) fail(fmt::format("unexpected end of file, expected {}", what));
    const size_t start = pos_;
    const int col = column();
    while (pos_ < text_.size() && !isNumberEnd(text_[pos_])) ++pos_;
    const std::string_view word = std::string_view(text_).substr(start, pos_ - start);
    const std::optional<double> value = quake::parseNumber(word);
    if (!value) failAt(line_, col, fmt::format("bad number '{}' for {}", printable(word), what));
    return *value;
  }

  // A quoted string. Quake's tools end it at the next '"' (no escapes); newlines are allowed.
  std::string quoted(const char* what) {
    skipSpaceAndComments();
    if (atEnd()) fail(fmt::format("unexpected end of file, expected {}", what));
    if (text_[pos_] != '"') fail(fmt::format("expected a quoted {}, found {}", what, describeHere()));
    const int startLine = line_;
    const int startCol = column();
    ++pos_;
    const size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '"') {
      if (text_[pos_] == '\n')
        newline();
      else
        ++pos_;
    }
    if (atEnd()) failAt(startLine, startCol, fmt::format("unterminated string ({})", what));
    std::string s(text_.substr(start, pos_ - start));
    ++pos_;
    return s;
  }

  // A bare word (texture name, block keyword): up to whitespace. Rejects control bytes, which
  // only binary garbage contains.
  std::string_view word(const char* what) {
    skipSpaceAndComments();
    if (atEnd()) fail(fmt::format("unexpected end of file, expected {}", what));
    const size_t start = pos_;
    while (pos_ < text_.size() && !isSpace(text_[pos_])) {
      const auto c = static_cast<unsigned char>(text_[pos_]);
      if (c < 0x20 || c == 0x7f) fail(fmt::format("unexpected byte 0x{:02x} in {}", c, what));
      ++pos_;
    }
    return text_.substr(start, pos_ - start);
  }

  // The text between the current '{' depth and its matching '}', which is consumed. Quoted
  // strings may hold braces; comments are kept as they are.
  std::string_view balancedBlock(int openLine, int openCol) {
    const size_t start = pos_;
    int depth = 1;
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        newline();
        continue;
      }
      if (c == '"') {
        ++pos_;
        while (pos_ < text_.size() && text_[pos_] != '"') {
          if (text_[pos_] == '\n')
            newline();
          else
            ++pos_;
        }
        if (pos_ < text_.size()) ++pos_;
        continue;
      }
      if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/') {
        skipToEndOfLine();
        continue;
      }
      if (c == '{') ++depth;
      if (c == '}' && --depth == 0) {
        std::string_view inner = text_.substr(start, pos_ - start);
        ++pos_;
        return inner;
      }
      ++pos_;
    }
    failAt(openLine, openCol, "unexpected end of file: this block's '{' is never closed");
  }

  std::string describeHere() const {
    if (atEnd()) return "end of file";
    const auto c = static_cast<unsigned char>(text_[pos_]);
    if (c < 0x20 || c >= 0x7f) return fmt::format("byte 0x{:02x}", c);
    size_t end = pos_;
    while (end < text_.size() && end - pos_ < 24 && !isSpace(text_[end])) ++end;
    return fmt::format("'{}'", text_.substr(pos_, std::max<size_t>(end - pos_, 1)));
  }

private:
  static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }
  static bool isNumberEnd(char c) { return isSpace(c) || c == ')' || c == ']' || c == '(' || c == '[' || c == '}' || c == '{'; }

  static std::string printable(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 32)) {
      const auto u = static_cast<unsigned char>(c);
      out += (u < 0x20 || u >= 0x7f) ? fmt::format("\\x{:02x}", u) : std::string(1, c);
    }
    if (s.size() > 32) out += "...";
    return out;
  }

  void newline() {
    ++pos_;
    ++line_;
    lineStart_ = pos_;
  }
  void skipToEndOfLine() {
    const size_t nl = text_.find('\n', pos_);
    pos_ = nl == std::string_view::npos ? text_.size() : nl;
  }

  std::string_view text_;
  const std::string& path_;
  size_t pos_ = 0;
  int line_ = 1;
  size_t lineStart_ = 0;
};

class Parser {
public:
  Parser(std::string_view text, const std::string& path) : in_(text, path) {}

  MapDocument parse() {
    MapDocument doc;
    while (true) {
      in_.skipSpaceAndComments();
      if (in_.atEnd()) break;
      const int line = in_.line();
      const int col = in_.column();
      in_.expect('{', "to open an entity");
      in_.skipSpaceAndComments();
      const char next = in_.peekChar();
      if (next == '(' || (next != '"' && next != '{' && next != '}' && next != '\0')) {
        // TrenchBroom's clipboard format: a bare brush (or patch) with no entity around it.
        MapEntity& world = implicitWorld(doc, line, col);
        world.brushes.push_back(parseBrushBody(line, col));
        continue;
      }
      doc.entities.push_back(parseEntityBody(line, col));
    }
    return doc;
  }

private:
  MapEntity& implicitWorld(MapDocument& doc, int line, int col) {
    if (doc.entities.empty() || !doc.entities.back().implicit) {
      MapEntity world;
      world.line = line;
      world.column = col;
      world.implicit = true;
      world.keys.emplace_back("classname", "worldspawn");
      doc.entities.push_back(std::move(world));
    }
    return doc.entities.back();
  }

  MapEntity parseEntityBody(int line, int col) {
    MapEntity e;
    e.line = line;
    e.column = col;
    while (true) {
      in_.skipSpaceAndComments();
      if (in_.atEnd()) in_.failAt(line, col, "unexpected end of file: this entity's '{' is never closed");
      const char c = in_.peekChar();
      if (c == '}') {
        in_.expect('}', "");
        return e;
      }
      if (c == '"') {
        std::string key = in_.quoted("entity key");
        std::string value = in_.quoted(fmt::format("value of key \"{}\"", key).c_str());
        e.keys.emplace_back(std::move(key), std::move(value));
        continue;
      }
      if (c == '{') {
        const int bl = in_.line();
        const int bc = in_.column();
        in_.expect('{', "");
        e.brushes.push_back(parseBrushBody(bl, bc));
        continue;
      }
      in_.fail(fmt::format("expected a \"key\", a brush '{{' or '}}' in entity, found {}", in_.describeHere()));
    }
  }

  // After a brush's '{': face lines, a brushDef, or a block we keep verbatim.
  MapBrush parseBrushBody(int line, int col) {
    MapBrush b;
    b.line = line;
    b.column = col;
    in_.skipSpaceAndComments();
    if (in_.atEnd()) in_.failAt(line, col, "unexpected end of file: this brush's '{' is never closed");
    const char c = in_.peekChar();
    if (c == '(' || c == '}') {
      while (true) {
        in_.skipSpaceAndComments();
        if (in_.atEnd()) in_.failAt(line, col, "unexpected end of file: this brush's '{' is never closed");
        if (in_.peekChar() == '}') {
          in_.expect('}', "");
          return b;
        }
        if (in_.peekChar() != '(') in_.fail(fmt::format("expected a face '(' or '}}' in brush, found {}", in_.describeHere()));
        b.faces.push_back(parseFace(false));
      }
    }
    // A keyword block. Look at the keyword without consuming: verbatim blocks keep it.
    const size_t keywordStart = in_.position();
    const int kwLine = in_.line();
    const int kwCol = in_.column();
    std::string_view keyword = in_.word("brush contents");
    if (keyword == "brushDef") {
      b.kind = MapBrush::Kind::BrushDef;
      in_.expect('{', "after brushDef");
      while (true) {
        in_.skipSpaceAndComments();
        if (in_.atEnd()) in_.failAt(kwLine, kwCol, "unexpected end of file: brushDef is never closed");
        if (in_.peekChar() == '}') break;
        b.faces.push_back(parseFace(true));
      }
      in_.expect('}', "to close brushDef");
      in_.expect('}', "to close the brush around brushDef");
      return b;
    }
    (void)keywordStart;
    // patchDef2, patchDef3, brushDef3 or something newer: keep the text, braces balanced.
    b.kind = MapBrush::Kind::Verbatim;
    b.keywordLine = kwLine;
    std::string_view rest = in_.balancedBlock(line, col);
    b.verbatim = std::string(keyword) + std::string(rest);
    return b;
  }

  dvec3 point() {
    in_.expect('(', "to open a plane point");
    dvec3 p;
    p.x = in_.number("plane point x");
    p.y = in_.number("plane point y");
    p.z = in_.number("plane point z");
    in_.expect(')', "to close a plane point");
    return p;
  }

  MapFace parseFace(bool brushPrimitive) {
    MapFace f;
    in_.skipSpaceAndComments();
    f.line = in_.line();
    f.column = in_.column();
    for (dvec3& p : f.points) p = point();

    if (brushPrimitive) {
      f.tex.kind = TextureKind::BrushPrimitive;
      in_.expect('(', "to open the brushDef texture matrix");
      for (auto& row : f.tex.matrix) {
        in_.expect('(', "to open a texture matrix row");
        for (double& v : row) v = in_.number("texture matrix");
        in_.expect(')', "to close a texture matrix row");
      }
      in_.expect(')', "to close the brushDef texture matrix");
      readTextureName(f);
    } else {
      readTextureName(f);
      in_.skipSpaceAndComments();
      if (in_.peekChar() == '[') {
        f.tex.kind = TextureKind::Valve220;
        for (int i = 0; i < 2; ++i) {
          in_.expect('[', "to open a Valve 220 texture axis");
          f.tex.axis[i].x = in_.number("texture axis x");
          f.tex.axis[i].y = in_.number("texture axis y");
          f.tex.axis[i].z = in_.number("texture axis z");
          f.tex.offset[i] = in_.number("texture offset");
          in_.expect(']', "to close a Valve 220 texture axis");
        }
        f.tex.rotation = in_.number("texture rotation");
        f.tex.scale[0] = in_.number("texture scale x");
        f.tex.scale[1] = in_.number("texture scale y");
      } else {
        f.tex.kind = TextureKind::Standard;
        f.tex.offset[0] = in_.number("texture offset x");
        f.tex.offset[1] = in_.number("texture offset y");
        f.tex.rotation = in_.number("texture rotation");
        f.tex.scale[0] = in_.number("texture scale x");
        f.tex.scale[1] = in_.number("texture scale y");
      }
    }
    readTrailingFields(f);
    return f;
  }

  void readTextureName(MapFace& f) {
    in_.skipSpaceAndComments();
    if (in_.peekChar() == '"') {
      f.quotedTexture = true;
      f.texture = in_.quoted("texture name");
    } else {
      f.texture = std::string(in_.word("texture name"));
    }
  }

  // What follows the texture parameters on the same line: Quake 2/3 contents, flags, value;
  // Hexen II's single value; Daikatana's colour after the Quake 2 fields; a comment.
  void readTrailingFields(MapFace& f) {
    std::array<double, 6> fields{};
    size_t count = 0;
    int firstLine = 0, firstCol = 0;
    while (true) {
      in_.skipSpaceOnLine();
      if (in_.atLineEnd()) break;
      if (in_.atComment()) {
        f.trailingComment = std::string(in_.restOfLine());
        break;
      }
      const char c = in_.peekChar();
      if (c == '}' || c == '(') break; // the next token is not ours even when on this line
      if (count == fields.size()) in_.fail("too many fields after the texture parameters");
      if (count == 0) {
        firstLine = in_.line();
        firstCol = in_.column();
      }
      fields[count++] = in_.number("surface field");
    }
    switch (count) {
    case 0: break;
    case 1: f.hexen2Value = fields[0]; break;
    case 3:
    case 6: {
      SurfaceAttributes s;
      s.contents = integerField(fields[0], firstLine, firstCol, "contents");
      s.flags = integerField(fields[1], firstLine, firstCol, "surface flags");
      s.value = fields[2];
      f.surface = s;
      if (count == 6)
        f.daikatanaColor = std::array<int, 3>{integerField(fields[3], firstLine, firstCol, "colour"),
                                              integerField(fields[4], firstLine, firstCol, "colour"),
                                              integerField(fields[5], firstLine, firstCol, "colour")};
      break;
    }
    default:
      in_.failAt(
          firstLine, firstCol,
          fmt::format(
              "{} fields after the texture parameters: expected none, 1 (Hexen II), 3 (Quake 2 contents, flags, value) or 6 (Daikatana)",
              count));
    }
  }

  int32_t integerField(double v, int line, int col, const char* what) {
    // Flags are bit masks; editors write them as integers (some as unsigned 32-bit).
    if (v != std::floor(v) || v < -2147483648.0 || v > 4294967295.0)
      in_.failAt(line, col, fmt::format("{} must be an integer, found {}", what, v));
    return static_cast<int32_t>(static_cast<int64_t>(v));
  }

  Scanner in_;
};

// "// Format: Valve" within the leading comment lines (TrenchBroom's header). A Quake 1 format
// under "// Game: Quake 2" is its Quake 2 form: ericw-tools' q2_hdrtest.map names "Valve" for
// Valve 220 face lines without Quake 2's optional surface flags, and qbsp -q2bsp compiles it as a
// Quake 2 level, so the game's light rules (range 1, no overbright) are Quake 2's.
std::optional<MapDialect> headerDialect(std::string_view text) {
  const auto value = [](std::string_view line, std::string_view key) -> std::optional<std::string_view> {
    if (line.substr(0, key.size()) != key) return std::nullopt;
    line.remove_prefix(key.size());
    while (!line.empty() && line.front() == ' ') line.remove_prefix(1);
    return line;
  };
  std::optional<MapDialect> format;
  bool quake2 = false;
  size_t pos = 0;
  for (int lines = 0; lines < 8 && pos < text.size(); ++lines) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
    if (line.empty()) continue;
    if (line.substr(0, 2) != "//") break;
    line.remove_prefix(2);
    while (!line.empty() && line.front() == ' ') line.remove_prefix(1);
    if (auto game = value(line, "Game:")) quake2 = *game == "Quake 2";
    if (auto name = value(line, "Format:")) {
      format = dialectFromFormatName(*name);
      break; // TrenchBroom writes the game first
    }
  }
  if (quake2 && format == MapDialect::Standard) return MapDialect::Quake2;
  if (quake2 && format == MapDialect::Valve220) return MapDialect::Quake2Valve;
  return format;
}

} // namespace

std::optional<MapDialect> dialectFromFormatName(std::string_view name) {
  struct Entry {
    std::string_view name;
    MapDialect dialect;
  };
  static constexpr std::array<Entry, 10> kNames{{
      {"Standard", MapDialect::Standard},
      {"Valve", MapDialect::Valve220},
      {"Quake2", MapDialect::Quake2},
      {"Quake2 (Valve)", MapDialect::Quake2Valve},
      {"Quake3", MapDialect::Quake3},
      {"Quake3 (legacy)", MapDialect::Quake3},
      {"Quake3 (Valve)", MapDialect::Quake3Valve},
      {"Hexen2", MapDialect::Hexen2},
      {"Daikatana", MapDialect::Daikatana},
      {"Heretic2", MapDialect::Quake2}, // Quake 2 face lines
  }};
  for (const Entry& e : kNames)
    if (e.name == name) return e.dialect;
  return std::nullopt;
}

MapDialect detectDialect(const MapDocument& doc) {
  bool valve = false, surface = false, hexen2 = false, daikatana = false, quake3 = false;
  for (const MapEntity& e : doc.entities) {
    if (const auto it = std::find_if(e.keys.begin(), e.keys.end(), [](const auto& kv) { return kv.first == "mapversion"; });
        it != e.keys.end() && it->second == "220")
      valve = true;
    for (const MapBrush& b : e.brushes) {
      if (b.kind != MapBrush::Kind::Brush) quake3 = true;
      for (const MapFace& f : b.faces) {
        valve |= f.tex.kind == TextureKind::Valve220;
        surface |= f.surface.has_value();
        hexen2 |= f.hexen2Value.has_value();
        daikatana |= f.daikatanaColor.has_value();
      }
    }
  }
  if (daikatana) return MapDialect::Daikatana;
  if (quake3) return valve ? MapDialect::Quake3Valve : MapDialect::Quake3;
  if (surface) return valve ? MapDialect::Quake2Valve : MapDialect::Quake2;
  if (hexen2) return MapDialect::Hexen2;
  return valve ? MapDialect::Valve220 : MapDialect::Standard;
}

MapDocument parseMap(std::string_view text, const std::string& path, std::optional<MapDialect> forced) {
  MapDocument doc = Parser(text, path).parse();
  doc.path = path;
  if (forced) {
    doc.dialect = *forced;
  } else if (auto header = headerDialect(text)) {
    doc.dialect = *header;
    doc.dialectFromHeader = true;
  } else {
    doc.dialect = detectDialect(doc);
  }
  return doc;
}

MapDocument readMapFile(const std::string& path, std::optional<MapDialect> forced) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw ImportError(Diagnostic{Severity::Error, path, 0, 0, "cannot open file"});
  std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) throw ImportError(Diagnostic{Severity::Error, path, 0, 0, "cannot read file"});
  return parseMap(text, path, forced);
}

} // namespace bt::map
