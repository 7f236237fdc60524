// Diagnostics: what an importer reports instead of silently skipping something.
#pragma once

#include <exception>
#include <string>
#include <vector>

namespace bt {

enum class Severity { Note, Warning, Error };

struct Diagnostic {
  Severity severity = Severity::Warning;
  std::string file;
  int line = 0;   // 1-based, 0 when not known
  int column = 0; // 1-based, 0 when not known
  std::string message;
};

// "file:line:col: warning: message", omitting what is unknown.
std::string format(const Diagnostic& d);

using Diagnostics = std::vector<Diagnostic>;

// Thrown by importers when the job cannot go on (malformed file, truncated BSP, ...).
// what() is already formatted as "file:line:col: error: message".
class ImportError : public std::exception {
public:
  explicit ImportError(Diagnostic d);
  const char* what() const noexcept override { return text_.c_str(); }
  const Diagnostic& diagnostic() const { return diagnostic_; }

private:
  Diagnostic diagnostic_;
  std::string text_;
};

} // namespace bt
