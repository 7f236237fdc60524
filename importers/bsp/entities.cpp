#include "importers/bsp/entities.h"

#include <fmt/format.h>

namespace bt::bsp {

namespace {

// A cursor over the lump text that knows its line and column, for error messages.
class EntityLexer {
public:
  EntityLexer(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  // Skips whitespace and `//` comments (some tools leave them in); false at the end.
  bool skipSpace() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/') {
        while (pos_ < text_.size() && text_[pos_] != '\n') advance();
      } else if (static_cast<unsigned char>(c) <= ' ') {
        advance();
      } else {
        return true;
      }
    }
    return false;
  }

  char peek() const { return text_[pos_]; }
  int line() const { return line_; }
  int column() const { return column_; }

  void expect(char c, const char* what) {
    if (!skipSpace()) fail(fmt::format("entities lump: unexpected end, expected {}", what));
    if (peek() != c) fail(fmt::format("entities lump: expected {}, found '{}'", what, peek()));
    advance();
  }

  // A quoted string; Quake's entity strings have no escapes and may not span lines.
  std::string quoted() {
    if (!skipSpace()) fail("entities lump: unexpected end, expected a quoted string");
    if (peek() != '"') fail(fmt::format("entities lump: expected a quoted string, found '{}'", peek()));
    const int startLine = line_, startColumn = column_;
    advance();
    const size_t begin = pos_;
    while (pos_ < text_.size() && text_[pos_] != '"') {
      if (text_[pos_] == '\n')
        throw ImportError(
            Diagnostic{Severity::Error, path_, startLine, startColumn, "entities lump: string runs past the end of its line"});
      advance();
    }
    if (pos_ >= text_.size())
      throw ImportError(Diagnostic{Severity::Error, path_, startLine, startColumn, "entities lump: unterminated string"});
    std::string s(text_.substr(begin, pos_ - begin));
    advance(); // closing quote
    return s;
  }

  [[noreturn]] void fail(std::string message) const {
    throw ImportError(Diagnostic{Severity::Error, path_, line_, column_, std::move(message)});
  }

private:
  void advance() {
    if (text_[pos_] == '\n') {
      ++line_;
      column_ = 1;
    } else {
      ++column_;
    }
    ++pos_;
  }

  std::string_view text_;
  const std::string& path_;
  size_t pos_ = 0;
  int line_ = 1;
  int column_ = 1;
};

} // namespace

std::vector<Entity> parseEntities(std::string_view text, const std::string& path) {
  EntityLexer lex(text, path);
  std::vector<Entity> entities;
  while (lex.skipSpace()) {
    Entity e;
    e.line = lex.line();
    lex.expect('{', "'{' opening an entity");
    while (true) {
      if (!lex.skipSpace())
        throw ImportError(Diagnostic{Severity::Error, path, e.line, 0, "entities lump: entity opened here is never closed"});
      if (lex.peek() == '}') {
        lex.expect('}', "'}'");
        break;
      }
      if (lex.peek() == '{') lex.fail("entities lump: '{' inside an entity (brushes do not belong here)");
      std::string key = lex.quoted();
      std::string value = lex.quoted();
      e.keys.emplace_back(std::move(key), std::move(value));
    }
    entities.push_back(std::move(e));
  }
  return entities;
}

} // namespace bt::bsp
