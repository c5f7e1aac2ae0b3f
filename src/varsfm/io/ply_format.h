#pragma once
// The PLY format itself, shared by every PLY reader in varsfm (point clouds in io/ply.cc, triangle
// meshes in texture/mesh_reader.cc) so the header grammar and the scalar types are parsed in one
// place. Supports ascii and binary_little_endian (byte-swapped on a big-endian host).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

namespace varsfm::ply {

// PLY's scalar types, by size and kind (each has two names: char / int8, ..., double / float64).
enum class ScalarType : uint8_t {
  kUnknown,
  kInt8,
  kUint8,
  kInt16,
  kUint16,
  kInt32,
  kUint32,
  kFloat32,
  kFloat64
};

// The type a name stands for; kUnknown for a name PLY does not define.
ScalarType ScalarTypeOf(const std::string& name);

// One property line: `property <type> <name>` or `property list <count_type> <type> <name>`.
struct Property {
  std::string name;
  std::string type;        // scalar type, or the list's item type
  std::string count_type;  // non-empty for a list
  // `type` and `count_type` decoded once, by ReadHeader, not per value read (a dense cloud has
  // tens of millions of values).
  ScalarType scalar = ScalarType::kUnknown;
  ScalarType count_scalar = ScalarType::kUnknown;

  bool IsList() const { return !count_type.empty(); }
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> properties;
};

struct Header {
  bool binary = false;  // binary_little_endian; false for ascii
  std::vector<Element> elements;
};

// Reads up to and including end_header. Throws varsfm::Error naming `file` for a file that is not
// PLY, an unsupported format, a missing end_header, or element counts the data after the header
// cannot hold (each record takes at least a byte per property; a record of no properties takes
// nothing, so such an element must be empty), which keeps a corrupt count from driving a reader
// into a near-endless loop or a huge allocation. Property types are not checked here: a reader
// checks those of the elements it uses (RequireKnownTypes), so it can skip the rest.
Header ReadHeader(std::istream& in, const std::filesystem::path& file);

// Throws varsfm::Error naming `file` when a property of `element` has an unknown type.
void RequireKnownTypes(const Element& element, const std::filesystem::path& file);

// A colour value as a byte: truncated, clamped to 0-255, NaN as 0 (foreign files may store
// colours as floats, out of range, or not as numbers at all).
uint8_t ColorByte(double value);

// Reads scalar values from the data after the header, ascii or binary.
class ValueReader {
 public:
  ValueReader(std::istream& in, bool binary) : in_(in), binary_(binary) {}
  // False when the data ends early or an ascii number is malformed; the caller names the place.
  bool Read(ScalarType type, double* value);
  // `size` bytes of binary data into `bytes`; false where the data ends early.
  bool ReadBytes(char* bytes, size_t size);
  bool binary() const { return binary_; }

 private:
  std::istream& in_;
  bool binary_;
};

// Reads one record of `element`: scalar k into (*scalars)[k], list k into (*lists)[k] (both
// resized to the property count; the entry of the other kind is left as it was). False when the
// data ends early or is malformed.
bool ReadRecord(ValueReader& reader, const Element& element, std::vector<double>* scalars,
                std::vector<std::vector<double>>* lists);

}  // namespace varsfm::ply
