#include "scene/diagnostics.h"

#include <fmt/format.h>

namespace bt {

std::string format(const Diagnostic& d) {
  std::string where = d.file;
  if (d.line > 0) where += fmt::format(":{}", d.line);
  if (d.line > 0 && d.column > 0) where += fmt::format(":{}", d.column);
  const char* kind = d.severity == Severity::Error ? "error" : d.severity == Severity::Warning ? "warning" : "note";
  return where.empty() ? fmt::format("{}: {}", kind, d.message) : fmt::format("{}: {}: {}", where, kind, d.message);
}

ImportError::ImportError(Diagnostic d) : diagnostic_(std::move(d)) {
  diagnostic_.severity = Severity::Error;
  text_ = format(diagnostic_);
}

} // namespace bt
