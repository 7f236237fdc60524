// The tokens of a Quake 3 shader script, as q3map2's and the engine's script readers split them:
// words, quoted strings and braces, `//` and `/* */` comments skipped, with the line each token
// starts on (for messages that name file and line).
#pragma once

#include <cstddef>
#include <string_view>

namespace bt::bsp {

class ShaderLexer {
public:
  explicit ShaderLexer(std::string_view text) : text_(text) {}

  // The next token, or empty at the end. `sameLine` stops at a line break (a keyword's arguments).
  std::string_view next(bool sameLine = false) {
    skipSpace(sameLine);
    if (pos_ >= text_.size() || isLineEnd(text_[pos_])) return {};
    tokenStart_ = pos_;
    const size_t begin = pos_;
    if (text_[pos_] == '{' || text_[pos_] == '}') return text_.substr(pos_++, 1);
    if (text_[pos_] == '"') {
      const size_t end = text_.find('"', pos_ + 1);
      if (end == std::string_view::npos) { // unterminated: the rest of the text
        pos_ = text_.size();
        return text_.substr(begin + 1);
      }
      pos_ = end + 1;
      return text_.substr(begin + 1, end - begin - 1);
    }
    while (pos_ < text_.size() && static_cast<unsigned char>(text_[pos_]) > ' ' && text_[pos_] != '{' && text_[pos_] != '}') ++pos_;
    return text_.substr(begin, pos_ - begin);
  }

  // Skips a keyword's remaining arguments, up to the line's end or a brace: some scripts put a
  // stage's closing brace on the same line, after a lone carriage return.
  void skipArguments() {
    while (pos_ < text_.size() && !isLineEnd(text_[pos_]) && text_[pos_] != '{' && text_[pos_] != '}') {
      if (text_[pos_] == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/') return;
      ++pos_;
    }
  }

  // The 1-based line of the last token next() returned.
  int line() {
    for (; counted_ < tokenStart_ && counted_ < text_.size(); ++counted_)
      if (text_[counted_] == '\n') ++line_;
    return line_;
  }

private:
  static bool isLineEnd(char c) { return c == '\n' || c == '\r'; }

  void skipSpace(bool sameLine) {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (isLineEnd(c) && sameLine) return;
      if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '*') {
        const size_t end = text_.find("*/", pos_ + 2);
        pos_ = end == std::string_view::npos ? text_.size() : end + 2;
      } else if (static_cast<unsigned char>(c) <= ' ') {
        ++pos_;
      } else {
        return;
      }
    }
  }

  std::string_view text_;
  size_t pos_ = 0;
  size_t tokenStart_ = 0;
  size_t counted_ = 0; // line_ counts the line breaks before this position
  int line_ = 1;
};

} // namespace bt::bsp
