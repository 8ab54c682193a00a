// What assimp 5.2.5 will read from an OBJ, OFF or PLY file, read first by us (see the header).
// The OFF and PLY readers below follow assimp's own code step for step (OFFLoader.cpp,
// PlyLoader.cpp, PlyParser.cpp, IOStreamBuffer.h, ParsingUtils.h, fast_atof.h), so that the
// counts they check are the counts assimp will allocate for. Where assimp reads stale bytes
// of earlier lines past a line's end, these readers see zeros; the few headers on which that
// differs are still bounded by the import child's memory limit (mesh_import.cpp).

#include "io/import_preflight.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include <fmt/format.h>

#include "hsr/error.hpp"

namespace hsr::detail {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kHeadBytes = 64 * 1024;  // a PLY or OFF header longer than this is not one
constexpr std::uint64_t kHuge = ~0ull;
using Traits = std::char_traits<char>;

// assimp's character classes (ParsingUtils.h)
bool isSpace(int c) { return c == ' ' || c == '\t'; }
bool isLineEnd(int c) { return c == '\r' || c == '\n' || c == '\0' || c == '\f'; }
bool isDigit(int c) { return c >= '0' && c <= '9'; }

// One more decimal digit of a count, saturating at 2^64 - 1 so that absurd counts stay absurd
// (assimp's strtoul10 wraps at 2^32 instead: a header claiming 2^32 + 3 elements is refused
// here, where assimp would read 3).
std::uint64_t appendDigit(std::uint64_t n, int c) {
  return n > (kHuge - 9) / 10 ? kHuge : n * 10 + static_cast<std::uint64_t>(c - '0');
}

std::string readHead(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(kHeadBytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

[[noreturn]] void refuseClaim(const fs::path& path, std::uint64_t claimed, const char* what,
                              std::uintmax_t bytes) {
  throw Error(path.string() + ": its header claims " + std::to_string(claimed) + " " + what +
              " but the file has only " + std::to_string(bytes) + " bytes");
}

// ---- OBJ ----------------------------------------------------------------------------------
// assimp reads a number's integer part and its exponent as 64-bit integers and, when one
// overflows (2^64 or more: 20 digits and up), returns 0 for the whole number: "v 1e99999 ..."
// or a 100-digit coordinate would load as 0. Digits after the point are safe (it reads 15 of
// them). Only vertex lines (v, vt, vn, vp) hold such numbers.
//
// Its time also grows with the square of the objects ("o" lines) and of the distinct material
// names ("usemtl") in a file (measured: 20,000 objects 0.7 s, 80,000 9.2 s, 300,000 over two
// minutes; 20,000 distinct names 2.7 s and 730 MB): past kMaxObjObjects or kMaxObjMaterials the
// file is refused at once, with the count, instead of at the import's deadline.
constexpr std::uint64_t kMaxObjObjects = 20'000;
constexpr std::size_t kMaxObjMaterials = 10'000;

// An OBJ is text: a NUL byte means the file is something else (1 GiB of zeros named .obj took
// assimp 33 s and 2 GB before it said "no polygons"), refused at the first one. Lines are read in
// pieces of a megabyte, and one longer than kMaxObjLine (no face of 32,767 vertices needs more
// than a few megabytes) is refused before it is held whole.
constexpr std::size_t kMaxObjLine = 64u << 20;

// The file's lines, one at a time, from a fixed-size buffer; throws on a NUL byte or a line
// past kMaxObjLine.
class ObjLines {
 public:
  explicit ObjLines(const fs::path& path)
      : path_(path), in_(path, std::ios::binary), buffer_(1u << 20) {}
  bool next(std::string& row) {
    row.clear();
    for (;;) {
      if (at_ == size_) {
        if (!in_) return !row.empty();
        in_.read(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
        size_ = static_cast<std::size_t>(std::max<std::streamsize>(in_.gcount(), 0));
        at_ = 0;
        if (size_ == 0) return !row.empty();
        if (const void* nul = std::memchr(buffer_.data(), '\0', size_))
          throw Error(fmt::format(
              "{}: a NUL byte at offset {}: not an OBJ file (OBJ is text)", path_.string(),
              offset_ +
                  static_cast<std::uint64_t>(static_cast<const char*>(nul) - buffer_.data())));
        offset_ += size_;
      }
      const char* begin = buffer_.data() + at_;
      const char* end = static_cast<const char*>(std::memchr(begin, '\n', size_ - at_));
      const std::size_t n = end ? static_cast<std::size_t>(end - begin) : size_ - at_;
      if (row.size() + n > kMaxObjLine)
        throw Error(
            fmt::format("{}: line {} is longer than {} MiB: not an OBJ file this reader takes",
                        path_.string(), line_ + 1, kMaxObjLine >> 20));
      row.append(begin, n);
      at_ += n + (end ? 1 : 0);
      if (end) {
        ++line_;
        return true;
      }
    }
  }

 private:
  fs::path path_;
  std::ifstream in_;
  std::vector<char> buffer_;
  std::size_t at_ = 0, size_ = 0;
  std::uint64_t offset_ = 0, line_ = 0;
};

void checkObjFile(const fs::path& path) {
  ObjLines obj(path);
  std::string row;
  std::uint64_t objects = 0, faces = 0;
  std::unordered_set<std::string> materials;
  const auto keyword = [&](std::size_t first, std::string_view word) {
    return row.compare(first, word.size(), word) == 0 &&
           (first + word.size() == row.size() || row[first + word.size()] == ' ' ||
            row[first + word.size()] == '\t');
  };
  for (std::uint64_t line_no = 1; obj.next(row); ++line_no) {
    const std::size_t first = row.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    if (keyword(first, "o") && ++objects > kMaxObjObjects)
      throw Error(
          fmt::format("{}: more than {} objects ('o' lines, counted to line {}): "
                      "assimp's OBJ reader slows down with the square of their number; "
                      "refused (merge objects, or convert the file)",
                      path.string(), kMaxObjObjects, line_no));
    if (keyword(first, "usemtl")) {
      std::string name = row.substr(first + 6);
      name.erase(0, std::min(name.find_first_not_of(" \t"), name.size()));
      materials.insert(std::move(name));
      if (materials.size() > kMaxObjMaterials)
        throw Error(
            fmt::format("{}: more than {} distinct material names ('usemtl', line {}): "
                        "assimp's OBJ reader slows down with the square of their number; "
                        "refused",
                        path.string(), kMaxObjMaterials, line_no));
    }
    faces += keyword(first, "f");
    if (row[first] != 'v') continue;
    for (std::size_t i = first; i < row.size();) {
      if (!isDigit(static_cast<unsigned char>(row[i]))) {
        ++i;
        continue;
      }
      const std::size_t run = i;
      std::uint64_t value = 0;
      while (i < row.size() && isDigit(static_cast<unsigned char>(row[i])))
        value = appendDigit(value, row[i++]);
      if ((run == 0 || row[run - 1] != '.') && value == kHuge)
        throw Error(path.string() + ": line " + std::to_string(line_no) + ": the number " +
                    row.substr(run, std::min<std::size_t>(i - run, 24)) +
                    (i - run > 24 ? "..." : "") + " (" + std::to_string(i - run) +
                    " digits) is too long for the OBJ reader");
    }
  }
  // No face, nothing to draw: said now, not after assimp has read it all (its import of a large
  // file of comments or vertices alone ends in "no polygons")
  if (faces == 0)
    throw Error(path.string() + ": no faces ('f' lines) in the file: an OBJ with nothing to draw");
}

// ---- OFF ----------------------------------------------------------------------------------
// OFFImporter::InternReadFile reads "[ST][C][N][4][n]OFF", an optional dimension, then the
// vertex and face counts with strtoul10 (leading digits; the rest of the word is ignored),
// skipping blanks, line ends and '#' comment lines between them, and allocates both arrays
// (up to 52 bytes a vertex, 16 a face) before it reads a line. Every vertex and face then
// needs a line of at least one character and its line end.
void checkOffCounts(const fs::path& path, std::uintmax_t bytes, std::string_view text) {
  std::size_t p = 0;
  const auto at = [&](std::size_t k) { return p + k < text.size() ? text[p + k] : '\0'; };
  const auto skipSpacesAndLineEnd = [&] {
    while (at(0) == ' ' || at(0) == '\t' || at(0) == '\r' || at(0) == '\n') ++p;
  };
  const auto skipLine = [&] {
    while (at(0) != '\r' && at(0) != '\n' && at(0) != '\0') ++p;
    while (at(0) == '\r' || at(0) == '\n') ++p;
  };
  const auto nextToken = [&] {  // OFFLoader.cpp's NextToken
    skipSpacesAndLineEnd();
    while (p < text.size() && (at(0) == '#' || at(0) == '\n' || at(0) == '\r')) {
      skipLine();
      skipSpacesAndLineEnd();
    }
  };
  const auto strtoul10 = [&] {
    std::uint64_t n = 0;
    while (isDigit(at(0))) n = appendDigit(n, text[p++]);
    return n;
  };
  nextToken();
  if (at(0) == 'S' && at(1) == 'T') p += 2;
  if (at(0) == 'C') ++p;
  if (at(0) == 'N') ++p;
  if (at(0) == '4') ++p;
  const bool has_dimension = at(0) == 'n';
  if (has_dimension) ++p;
  if (at(0) == 'O' && at(1) == 'F' && at(2) == 'F') {
    p += 3;
    nextToken();
  } else {
    nextToken();
    if (!isDigit(at(0))) return;  // assimp: "OFF: Header is invalid"
  }
  if (has_dimension) {
    if (strtoul10() > 3) return;  // assimp refuses more than 3 dimensions itself
    nextToken();
  }
  nextToken();
  const std::uint64_t vertices = strtoul10();
  nextToken();
  const std::uint64_t faces = strtoul10();
  const std::uint64_t lines = bytes / 2 + 1;
  if (vertices > lines) refuseClaim(path, vertices, "vertices", bytes);
  if (faces > lines) refuseClaim(path, faces, "faces", bytes);
  if (vertices + faces > lines) refuseClaim(path, vertices + faces, "vertices and faces", bytes);
}

// ---- PLY ----------------------------------------------------------------------------------

// IOStreamBuffer::getNextLine over the file: a line ends at '\r', '\n', '\0' or '\f'; standing
// on a line end, it first skips to just past the next '\n' (so CRLF and one empty line vanish).
// A last line without its end still counts. Reads the line character by character, so that a
// data line of any length costs no memory.
class LineReader {
 public:
  explicit LineReader(std::streambuf& in) : in_(in) {}
  // Moves to the next line; false at the end of the file.
  bool startLine() {
    int c = in_.sgetc();
    if (c == Traits::eof()) return false;
    if (isLineEnd(c)) {
      do {
        c = bump();
      } while (c != Traits::eof() && c != '\n');
      if (in_.sgetc() == Traits::eof()) return false;
    }
    return true;
  }
  // The current character of the line, '\n' at its end.
  int peek() {
    const int c = in_.sgetc();
    return c == Traits::eof() || isLineEnd(c) ? '\n' : c;
  }
  void advance() {
    if (peek() != '\n') bump();
  }
  // Steps over the rest of the line and its one line-end character.
  void finishLine() {
    while (peek() != '\n') bump();
    last_end_ = in_.sgetc() != Traits::eof() ? bump() : Traits::eof();
  }
  // The character that ended the last line (EOF if the file did).
  int lastLineEnd() const { return last_end_; }
  bool nextLine(std::string* line) {
    if (!startLine()) return false;
    line->clear();
    for (int c; (c = peek()) != '\n' && line->size() <= kHeadBytes; bump())
      line->push_back(static_cast<char>(c));
    finishLine();
    return true;
  }
  std::uint64_t offset() const { return offset_; }
  std::streambuf& buffer() { return in_; }

 private:
  int bump() {
    const int c = in_.sbumpc();
    if (c != Traits::eof()) ++offset_;
    return c;
  }
  std::streambuf& in_;
  std::uint64_t offset_ = 0;
  int last_end_ = Traits::eof();
};

// One header line as assimp's parser sees it: the line, then '\n', then (where assimp's buffer
// holds stale bytes of earlier lines) zeros. The steps are ParsingUtils.h's, as PLY::DOM's
// wrappers apply them (each erases what it stepped over: here, the cursor moves).
class LineCursor {
 public:
  LineCursor() = default;
  explicit LineCursor(std::string line) : line_(std::move(line)) {}
  char at(std::size_t k = 0) const {
    const std::size_t i = pos_ + k;
    return i < line_.size() ? line_[i] : i == line_.size() ? '\n' : '\0';
  }
  bool skipSpaces() {
    while (isSpace(at())) ++pos_;
    return !isLineEnd(at());
  }
  void skipSpacesAndLineEnd() {
    while (isSpace(at()) || at() == '\r' || at() == '\n') ++pos_;
  }
  bool startsWith(std::string_view text) const {
    for (std::size_t k = 0; k < text.size(); ++k)
      if (at(k) != text[k]) return false;
    return true;
  }
  void skipLine() {
    while (at() != '\r' && at() != '\n' && at() != '\0') ++pos_;
    while (at() == '\r' || at() == '\n') ++pos_;
  }
  // The token, then one separator (space, tab or line end), which is stepped over too
  bool tokenMatch(std::string_view token) {
    for (std::size_t k = 0; k < token.size(); ++k)
      if (at(k) != token[k]) return false;
    const char next = at(token.size());
    if (!isSpace(next) && !isLineEnd(next)) return false;
    pos_ += token.size() + (next != '\0' ? 1 : 0);
    return true;
  }
  std::uint64_t strtoul10() {
    std::uint64_t n = 0;
    while (isDigit(at())) n = appendDigit(n, at(0)), ++pos_;
    return n;
  }
  std::string word() const {
    std::string w;
    for (std::size_t k = 0; w.size() < 32 && !isSpace(at(k)) && !isLineEnd(at(k)); ++k)
      w.push_back(at(k));
    return w;
  }
  // PLY::DOM::SkipComments: a comment line is stepped over, unless it names a TextureFile
  void skipComments() {
    LineCursor n = *this;
    if (!n.skipSpaces() || !n.tokenMatch("comment")) return;
    if (!n.skipSpaces()) n.skipLine();
    if (n.tokenMatch("TextureFile")) return;
    n.skipLine();
    *this = n;
  }

 private:
  std::string line_;
  std::size_t pos_ = 0;
};

// A PLY data type: its size in binary files and how assimp converts it to a list length.
struct PlyType {
  int size = 0;   // 0: not a type assimp knows
  char kind = 0;  // 'u' unsigned, 's' signed, 'f' floating point
};

// PLY::Property::ParseDataType: assimp's names, tried in its order (int32 before int, float
// before float32), each followed by a separator.
PlyType parseDataType(LineCursor& c) {
  static constexpr struct {
    std::string_view name;
    PlyType type;
  } kTypes[] = {{"char", {1, 's'}},   {"int8", {1, 's'}},    {"uchar", {1, 'u'}},
                {"uint8", {1, 'u'}},  {"short", {2, 's'}},   {"int16", {2, 's'}},
                {"ushort", {2, 'u'}}, {"uint16", {2, 'u'}},  {"int32", {4, 's'}},
                {"int", {4, 's'}},    {"uint32", {4, 'u'}},  {"uint", {4, 'u'}},
                {"float", {4, 'f'}},  {"float32", {4, 'f'}}, {"double64", {8, 'f'}},
                {"double", {8, 'f'}}, {"float64", {8, 'f'}}};
  for (const auto& t : kTypes)
    if (c.tokenMatch(t.name)) return t.type;
  return {};
}

struct PlyProperty {
  PlyType item;
  PlyType length;  // size > 0: a list, its length stored as this type
};

enum class PlySemantic { kVertex, kFace, kTriStrip, kEdge, kMaterial, kTextureFile, kOther };

struct PlyElement {
  std::string name;
  PlySemantic semantic = PlySemantic::kOther;
  std::uint64_t count = 0;
  std::vector<PlyProperty> props;
};

// PLY::Property::ParseProperty: "property TYPE NAME" or "property list TYPE TYPE NAME".
bool parseProperty(LineCursor& c, PlyProperty* out) {
  if (!c.skipSpaces() || !c.tokenMatch("property") || !c.skipSpaces()) return false;
  if (c.tokenMatch("list")) {
    out->length = parseDataType(c);
    if (out->length.size == 0) {
      c.skipLine();
      return false;
    }
    if (!c.skipSpaces()) return false;
  }
  out->item = parseDataType(c);
  if (out->item.size == 0) {
    c.skipLine();
    return false;
  }
  return c.skipSpaces();  // a name must follow; which one does not change the data's layout
}

// PLY::Element::ParseElement: "element NAME COUNT" (assimp also takes "comment" for
// "element"), then one property a line until a line that is not one (a comment ends the
// list too). The cursor is left on that line. A known name must be followed by a separator;
// an unknown one is not stepped over, so its count is read from the name itself.
bool parseElement(LineCursor& c, LineReader& lines, PlyElement* out) {
  if (!c.skipSpaces()) return false;
  if (!c.tokenMatch("element") && !c.tokenMatch("comment")) return false;
  if (!c.skipSpaces()) return false;
  static constexpr struct {
    std::string_view name;
    PlySemantic semantic;
  } kSemantics[] = {
      {"vertex", PlySemantic::kVertex},      {"face", PlySemantic::kFace},
      {"tristrips", PlySemantic::kTriStrip}, {"edge", PlySemantic::kEdge},
      {"material", PlySemantic::kMaterial},  {"TextureFile", PlySemantic::kTextureFile}};
  out->name = c.word();
  for (const auto& s : kSemantics) {
    if (c.tokenMatch(s.name)) {
      out->semantic = s.semantic;
      out->name = s.name;
      break;
    }
  }
  if (!c.skipSpaces()) return false;
  if (out->semantic == PlySemantic::kTextureFile) return true;  // no count, no properties
  out->count = c.strtoul10();
  for (;;) {
    if (lines.offset() > kHeadBytes) return true;  // the header loop refuses such a header
    std::string line;
    c = lines.nextLine(&line) ? LineCursor(std::move(line)) : LineCursor();
    c.skipComments();
    PlyProperty p;
    if (!parseProperty(c, &p)) return true;
    out->props.push_back(p);
  }
}

// A list length as assimp converts it: ConvertTo<unsigned int> of the stored type (a negative
// signed length becomes 2^32 - |n|; a floating-point one beyond unsigned int is refused).
std::uint64_t lengthFromBits(std::uint64_t bits, PlyType type) {
  switch (type.kind) {
    case 'u':
      return bits;
    case 's': {
      const int shift = 64 - 8 * type.size;
      const auto v = static_cast<std::int64_t>(bits << shift) >> shift;
      return static_cast<std::uint32_t>(v);
    }
    default: {
      double v;
      if (type.size == 4) {
        float f;
        const auto b = static_cast<std::uint32_t>(bits);
        std::memcpy(&f, &b, 4);
        v = f;
      } else {
        std::memcpy(&v, &bits, 8);
      }
      return v >= 0 && v < 4294967296.0 ? static_cast<std::uint64_t>(v) : kHuge;
    }
  }
}

std::uint64_t lengthFromText(const std::string& token, PlyType type) {
  if (type.kind == 'f') {
    const double v = std::strtod(token.c_str(), nullptr);
    return v >= 0 && v < 4294967296.0 ? static_cast<std::uint64_t>(v) : kHuge;
  }
  std::size_t i = 0;
  bool negative = false;
  if (type.kind == 's' && (token[0] == '-' || token[0] == '+')) negative = token[i++] == '-';
  std::uint64_t n = 0;  // strtoul10 / strtol10: leading digits
  for (; i < token.size() && isDigit(token[i]); ++i) n = appendDigit(n, token[i]);
  return negative && n > 0 ? kHuge : n;
}

// PlyLoader::InternReadFile and PLY::DOM::ParseHeader, then the data walked as
// ParseInstanceList(Binary) reads it, nothing stored.
HeaderFix checkPlyFile(const fs::path& path, std::uintmax_t bytes) {
  const std::string file = path.string();
  HeaderFix fix;
  std::filebuf fb;
  if (!fb.open(path, std::ios::in | std::ios::binary)) return fix;  // assimp will say why
  LineReader lines(fb);
  const auto noEndHeader = [&] {
    return Error(file + ": its PLY header has no end_header line" +
                 (lines.offset() > kHeadBytes ? " in its first 64 KiB" : ""));
  };

  // The magic line, then the format on the second line (later "format" lines are ignored)
  std::string line;
  const auto is = [&](std::size_t i, char lower) {
    return line[i] == lower || line[i] == lower - 'a' + 'A';
  };
  if (!lines.nextLine(&line) || line.size() < 3 || !is(0, 'p') || !is(1, 'l') || !is(2, 'y'))
    return fix;
  if (!lines.nextLine(&line)) throw noEndHeader();
  LineCursor format_line(line);
  format_line.skipSpacesAndLineEnd();
  bool binary = false, big_endian = false;
  if (!format_line.tokenMatch("format")) return fix;  // assimp: "Missing format specification"
  if (!format_line.tokenMatch("ascii")) {
    if (!format_line.startsWith("binary_")) return fix;  // assimp: "Unknown file format"
    binary = true;
    big_endian = format_line.at(7) == 'b' || format_line.at(7) == 'B';
  }

  // The header: elements and their properties, up to an end_header line
  std::vector<PlyElement> elements;
  LineCursor c;
  if (!lines.nextLine(&line)) throw noEndHeader();
  c = LineCursor(line);
  for (;;) {
    c.skipComments();
    PlyElement e;
    if (parseElement(c, lines, &e)) {
      elements.push_back(std::move(e));
    } else if (c.tokenMatch("end_header")) {
      break;
    } else if (lines.offset() > kHeadBytes || !lines.nextLine(&line)) {
      throw noEndHeader();
    } else {
      c = LineCursor(line);
    }
  }

  // Counts against the file: every element takes at least a byte or a line
  std::uint64_t total = 0;
  int vertex_elements = 0, face_elements = 0;
  for (const PlyElement& e : elements) {
    total = e.count > kHuge - total ? kHuge : total + e.count;
    if (e.count == 0) continue;
    vertex_elements += e.semantic == PlySemantic::kVertex;
    face_elements += e.semantic == PlySemantic::kFace || e.semantic == PlySemantic::kTriStrip;
  }
  if (total > bytes) refuseClaim(path, total, "elements (vertices, faces...)", bytes);
  // PlyLoader sizes its vertex and face arrays by the first such element and writes every
  // later one into them: a second one overflows the heap
  if (vertex_elements > 1 || face_elements > 1)
    throw Error(file + ": its PLY header declares " +
                (vertex_elements > 1 ? "a second vertex element" : "a second face element") +
                ", which the PLY reader writes past its arrays");

  if (binary) {
    // The data starts after end_header's line end; assimp drops a '\n' there, meant for the
    // second half of "\r\n". After a bare "\n" that byte is data: the import then inserts
    // the '\r' that makes assimp read it right (HeaderFix), and the walk keeps the byte.
    std::streambuf& buf = lines.buffer();
    std::uint64_t offset = lines.offset();
    if (buf.sgetc() == '\n') {
      if (lines.lastLineEnd() == '\n') {
        fix.insert_cr_at = offset - 1;
      } else {
        buf.sbumpc();
        ++offset;
      }
    }
    std::uint64_t left = bytes > offset ? bytes - offset : 0;
    char skipped[4096];
    const auto skip = [&](std::uint64_t n) {
      left -= n;
      if (n > sizeof skipped) {
        buf.pubseekoff(static_cast<std::streamoff>(n), std::ios::cur, std::ios::in);
        return;
      }
      buf.sgetn(skipped, static_cast<std::streamsize>(n));
    };
    for (const PlyElement& e : elements) {
      std::uint64_t row = 0;  // bytes of an element without lists
      bool lists = false;
      for (const PlyProperty& p : e.props) {
        row += static_cast<std::uint64_t>(p.length.size > 0 ? 0 : p.item.size);
        lists = lists || p.length.size > 0;
      }
      const auto ends = [&](std::uint64_t i) {
        return Error(file + ": its data ends inside " + e.name + " " + std::to_string(i) +
                     " (the header declares " + std::to_string(e.count) + ")");
      };
      if (!lists) {
        if (row > 0 && e.count > left / row) throw ends(left / row);
        skip(e.count * row);
        continue;
      }
      for (std::uint64_t i = 0; i < e.count; ++i) {
        for (const PlyProperty& p : e.props) {
          if (p.length.size == 0) {
            if (static_cast<std::uint64_t>(p.item.size) > left) throw ends(i);
            skip(static_cast<std::uint64_t>(p.item.size));
            continue;
          }
          unsigned char raw[8] = {};
          if (static_cast<std::uint64_t>(p.length.size) > left) throw ends(i);
          left -= static_cast<std::uint64_t>(p.length.size);
          buf.sgetn(reinterpret_cast<char*>(raw), p.length.size);
          std::uint64_t bits = 0;
          for (int k = 0; k < p.length.size; ++k)
            bits |= static_cast<std::uint64_t>(raw[big_endian ? p.length.size - 1 - k : k])
                    << (8 * k);
          const std::uint64_t length = lengthFromBits(bits, p.length);
          if (length > left / static_cast<std::uint64_t>(p.item.size))
            throw Error(file + ": " + e.name + " " + std::to_string(i) + " has a list of " +
                        std::to_string(length) + " entries but only " + std::to_string(left) +
                        " bytes follow");
          skip(length * static_cast<std::uint64_t>(p.item.size));
        }
      }
    }
    return fix;
  }

  // ASCII: one line per element, every element read (assimp repeats the last line for each one
  // the data lacks); a list's length must not exceed the values after it on its line
  std::uint64_t data_lines = 0;
  std::string token;
  for (const PlyElement& e : elements) {
    const bool parsed = e.semantic != PlySemantic::kOther && !e.props.empty();
    for (std::uint64_t i = 0; i < e.count; ++i) {
      if (!lines.startLine())
        throw Error(file + ": its header declares " + std::to_string(total) +
                    " elements but its data has only " + std::to_string(data_lines) + " lines");
      ++data_lines;
      for (std::size_t k = 0; parsed && k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        // A value: spaces, then the characters up to the next space or the line's end
        const auto nextValue = [&](std::string* text) {
          while (isSpace(lines.peek())) lines.advance();
          if (lines.peek() == '\n') return false;
          if (text) text->clear();
          for (int ch; (ch = lines.peek()) != '\n' && !isSpace(ch); lines.advance())
            if (text && text->size() < 64) text->push_back(static_cast<char>(ch));
          return true;
        };
        if (!nextValue(p.length.size > 0 ? &token : nullptr)) break;  // assimp: default values
        if (p.length.size == 0) continue;
        const std::uint64_t length = lengthFromText(token, p.length);
        for (std::uint64_t v = 0; v < length; ++v)
          if (!nextValue(nullptr))
            throw Error(file + ": " + e.name + " " + std::to_string(i) + " has a list of " +
                        std::to_string(length) + " entries but its line holds " +
                        std::to_string(v) + " values");
      }
      lines.finishLine();
    }
  }
  return fix;
}

// A PLY file by content, as assimp recognises one whatever its extension
bool startsAsPly(std::string_view head) {
  return head.rfind("ply\n", 0) == 0 || head.rfind("ply\r", 0) == 0;
}

}  // namespace

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

namespace {

// ---- What a file says it is ----------------------------------------------------------------
// A PLY, OFF, STL or glTF file whose first bytes are not its format's is refused before assimp
// reads it: assimp reads a file whole before it looks, so 1 GiB of zeros named .stl or .gltf
// took 14 s and 1 GB to be refused (.off 7 s, .ply 7 s). The checks are the formats' own: PLY
// begins with "ply", OFF's first word ends in "OFF", an STL is binary when its size is 84 + 50
// bytes per triangle of its count and otherwise text beginning with "solid", a .gltf is JSON.
std::string_view firstWord(std::string_view head) {
  std::size_t a = 0;
  while (a < head.size() &&
         (head[a] == ' ' || head[a] == '\t' || head[a] == '\r' || head[a] == '\n'))
    ++a;
  std::size_t b = a;
  while (b < head.size() && !(head[b] == ' ' || head[b] == '\t' || head[b] == '\r' ||
                              head[b] == '\n' || head[b] == '\0'))
    ++b;
  return head.substr(a, b - a);
}

bool startsWithNoCase(std::string_view s, std::string_view prefix) {
  if (s.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[i])) != prefix[i]) return false;
  return true;
}

void checkWhatItSays(const fs::path& path, const std::string& ext, std::uintmax_t bytes,
                     std::string_view head) {
  const auto refuse = [&](const std::string& why) { throw Error(path.string() + ": " + why); };
  if (ext == ".ply" && !startsWithNoCase(head, "ply"))
    refuse("not a PLY file (it does not begin with 'ply')");
  if (ext == ".off") {
    const std::string_view word = firstWord(head);
    if (word.size() < 3 || word.substr(word.size() - 3) != "OFF")
      refuse("not an OFF file (its first word is not OFF, COFF, NOFF, STOFF, 4OFF, ...)");
  }
  if (ext == ".stl") {
    std::uint32_t count = 0;
    if (head.size() >= 84) std::memcpy(&count, head.data() + 80, 4);  // little-endian, as x86
    const bool binary = head.size() >= 84 && std::uint64_t{84} + std::uint64_t{50} * count == bytes;
    if (!binary && !startsWithNoCase(firstWord(head), "solid"))
      refuse(
          fmt::format("not an STL file: not a binary one (84 bytes and 50 a triangle: its count {} "
                      "asks for {} bytes, the file has {}) and not a text one (it does not begin "
                      "with 'solid')",
                      count, std::uint64_t{84} + std::uint64_t{50} * count, bytes));
  }
  if (ext == ".gltf") {
    // a BOM
    const std::string_view text = head.substr(0, 3) == "\xEF\xBB\xBF" ? head.substr(3) : head;
    const std::string_view word = firstWord(text);
    if (word.empty() || word.front() != '{')
      refuse("not a glTF file (a .gltf is JSON, beginning with '{')");
  }
}

}  // namespace

HeaderFix checkHeaderAgainstSize(const fs::path& path, std::uintmax_t bytes) {
  const std::string ext = lowerExtension(path);
  if (ext == ".obj") {
    checkObjFile(path);
    return {};
  }
  const std::string head = readHead(path);
  checkWhatItSays(path, ext, bytes, head);
  if (ext == ".ply" || startsAsPly(head)) return checkPlyFile(path, bytes);
  if (ext == ".off") checkOffCounts(path, bytes, head);
  return {};
}

}  // namespace hsr::detail
