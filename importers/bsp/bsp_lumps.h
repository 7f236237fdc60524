// The lump reader the per-game BSP readers share (bsp_file_q1.cpp, bsp_file_q2.cpp,
// bsp_file_q3.cpp): the lump table, fixed-size records, index and range checks that fail naming
// the file and the lump, and the tree checks the games have in common. Internal to importers/bsp.
#pragma once

#include "importers/bsp/bsp_file.h"
#include "quake/binary_reader.h"
#include "scene/diagnostics.h"

#include <fmt/format.h>
#include <glm/vec3.hpp>

#include <bit>
#include <cstring>
#include <span>
#include <string>
#include <vector>

namespace bt::bsp::detail {

// Fields of one record (quake/binary_reader.h).
using FieldReader = quake::LittleEndianReader;

struct Lump {
  const char* name;
  std::span<const uint8_t> bytes;
};

class Reader {
public:
  Reader(std::span<const uint8_t> file, const std::string& path) : file_(file), path_(path) {}

  [[noreturn]] void fail(std::string message) const { throw ImportError(Diagnostic{Severity::Error, path_, 0, 0, std::move(message)}); }
  [[noreturn]] void fail(const Lump& lump, std::string message) const { fail(fmt::format("lump '{}': {}", lump.name, message)); }

  const std::string& path() const { return path_; }
  std::span<const uint8_t> file() const { return file_; }

  // Reads `count` lump directory entries (offset, length) starting at byte `tableOffset`.
  std::vector<Lump> lumpTable(size_t tableOffset, const char* const* names, int count) const {
    const size_t tableEnd = tableOffset + static_cast<size_t>(count) * 8;
    if (file_.size() < tableEnd)
      fail(fmt::format("header: file is {} bytes, too short for the lump table ({} bytes)", file_.size(), tableEnd));
    std::vector<Lump> lumps;
    FieldReader r(file_.subspan(tableOffset));
    for (int i = 0; i < count; ++i) {
      const int64_t offset = r.i32();
      const int64_t length = r.i32();
      Lump lump{names[i], {}};
      if (offset < 0 || length < 0) fail(lump, fmt::format("negative offset {} or length {} in the lump table", offset, length));
      if (static_cast<uint64_t>(offset + length) > file_.size())
        fail(lump, fmt::format("offset {} + length {} lies past the end of the file ({} bytes)", offset, length, file_.size()));
      lump.bytes = file_.subspan(static_cast<size_t>(offset), static_cast<size_t>(length));
      lumps.push_back(lump);
    }
    return lumps;
  }

  // Splits a lump into fixed-size records and parses each with parse(FieldReader&).
  template <class Record, class Parse> std::vector<Record> records(const Lump& lump, size_t recordSize, Parse parse) const {
    if (lump.bytes.size() % recordSize != 0)
      fail(lump, fmt::format("length {} is not a multiple of the record size {}", lump.bytes.size(), recordSize));
    const size_t count = lump.bytes.size() / recordSize;
    std::vector<Record> out;
    out.reserve(count);
    for (size_t i = 0; i < count; ++i) {
      FieldReader r(lump.bytes.subspan(i * recordSize, recordSize));
      out.push_back(parse(r));
    }
    return out;
  }

  // Fails unless 0 <= value < count.
  void checkIndex(const Lump& lump, size_t record, const char* what, int64_t value, size_t count) const {
    if (value < 0 || static_cast<uint64_t>(value) >= count)
      fail(lump, fmt::format("record {} refers to {} {}, but there are {}", record, what, value, count));
  }
  // Fails unless [first, first + n) lies inside [0, count).
  void checkRange(const Lump& lump, size_t record, const char* what, int64_t first, int64_t n, size_t count) const {
    if (first < 0 || n < 0 || static_cast<uint64_t>(first + n) > count)
      fail(lump, fmt::format("record {} refers to {} {}..{}, but there are {}", record, what, first, first + n, count));
  }

private:
  std::span<const uint8_t> file_;
  const std::string& path_;
};

// The entities lump as text, up to its NUL.
std::string entitiesText(const Lump& lump);
std::vector<uint8_t> copyBytes(const Lump& lump);

// Nodes: plane, both children (a node or, below zero, leaf -1 - child) and, for Quake 1 and 2,
// the node's run of faces.
void checkNodes(const Reader& reader, const Lump& lump, const BspFile& bsp, bool nodesHaveFaces);
// Q2/Q3 leafs: their runs of leaf faces (named `faceRuns` as the game names that lump) and of
// leaf brushes.
void checkLeafRuns(const Reader& reader, const Lump& lump, const BspFile& bsp, const char* faceRuns);
// Building a brush clips each side by every other one; compilers stay far below this (qbsp3's
// MAX_BUILD_SIDES is 128), and a corrupt count must not turn into hours of clipping.
void checkBrushSideCount(const Reader& reader, const Lump& lump, size_t record, int32_t sideCount);
// Checks shared by Q1 and Q2: faces -> surfedges -> edges -> vertices, faces -> planes, texinfo.
void checkFaceChain(const Reader& reader, const BspFile& bsp);
// ericw-tools appends a directory of named extension lumps after the last standard lump,
// aligned to 4 bytes: "BSPX", int32 count, then {char name[24]; int32 offset, length} each.
void readBspx(const Reader& reader, BspFile& bsp, std::span<const Lump> lumps);

// The games' readers: every lump of the version in bsp.version, checked.
void readQuake1(const Reader& reader, BspFile& bsp); // BSP29, BSP2, 2PSB, BSP30
void readQuake2(const Reader& reader, BspFile& bsp); // IBSP 38
void readQuake3(const Reader& reader, BspFile& bsp); // IBSP 46

} // namespace bt::bsp::detail
