#include "varsfm/io/ply_format.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <sstream>

#include "varsfm/io/text_line.h"
#include "varsfm/util/error.h"
#include "varsfm/util/little_endian.h"

namespace varsfm::ply {
namespace {

// `bytes` (little-endian, as PLY's binary format stores them) as a double.
double Decode(const char* bytes, ScalarType type) {
  auto as = [&]<typename T>(T) { return static_cast<double>(GetLittleEndian<T>(bytes)); };
  switch (type) {
    case ScalarType::kInt8:
      return as(int8_t{});
    case ScalarType::kUint8:
      return as(uint8_t{});
    case ScalarType::kInt16:
      return as(int16_t{});
    case ScalarType::kUint16:
      return as(uint16_t{});
    case ScalarType::kInt32:
      return as(int32_t{});
    case ScalarType::kUint32:
      return as(uint32_t{});
    case ScalarType::kFloat32:
      return as(float{});
    default:
      return as(double{});
  }
}

// Bytes of each ScalarType, in the enum's order (kUnknown: 0).
size_t SizeOf(ScalarType type) {
  static constexpr size_t kBytes[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
  return kBytes[static_cast<size_t>(type)];
}

// The bytes of a record of `element` when all its properties are scalars of known types; 0
// otherwise (a list's length is in the data).
size_t FixedRecordSize(const Element& element) {
  size_t bytes = 0;
  for (const Property& p : element.properties) {
    if (p.IsList() || p.scalar == ScalarType::kUnknown) return 0;
    bytes += SizeOf(p.scalar);
  }
  return bytes;
}

// Largest record read in one go: a point cloud's vertex (x y z nx ny nz red green blue, even as
// doubles) is well below it.
constexpr size_t kMaxFixedRecord = 256;

// Reads a binary record of `size` (FixedRecordSize, at most kMaxFixedRecord) bytes in one read
// (each value through the stream on its own was most of the time to read tens of millions of
// points) and decodes it into (*scalars)[k]. False where the data ends early.
bool ReadFixedRecord(ValueReader& reader, const Element& element, size_t size,
                     std::vector<double>* scalars) {
  char bytes[kMaxFixedRecord];
  if (!reader.ReadBytes(bytes, size)) return false;
  size_t at = 0;
  for (size_t k = 0; k < element.properties.size(); ++k) {
    const Property& p = element.properties[k];
    (*scalars)[k] = Decode(bytes + at, p.scalar);
    at += SizeOf(p.scalar);
  }
  return true;
}

// Throws unless every element's records fit in the bytes after the header (see ReadHeader).
void RequireCountsFit(const Header& header, std::istream& in, const std::filesystem::path& file) {
  const std::streampos start = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streampos end = in.tellg();
  in.seekg(start);
  if (start < 0 || end < start) Fail("{}: cannot find the size of the PLY data", file.string());
  uint64_t left = static_cast<uint64_t>(end - start);
  for (const Element& e : header.elements) {
    // The least a record can take: binary, each scalar's bytes and each list's count; ascii, a
    // character per property.
    uint64_t record = 0;
    for (const Property& p : e.properties)
      record +=
          header.binary ? std::max<size_t>(SizeOf(p.IsList() ? p.count_scalar : p.scalar), 1) : 1;
    if (e.count > 0 && record == 0)
      Fail("{}: PLY element {} has {} records but no properties", file.string(), e.name, e.count);
    if (record > 0 && e.count > left / record)
      Fail("{}: PLY header declares {} {} records, more than the data after it can hold",
           file.string(), e.count, e.name);
    left -= record * e.count;
  }
}

}  // namespace

uint8_t ColorByte(double value) {
  if (!(value > 0)) return 0;  // also NaN
  return value >= 255 ? uint8_t{255} : static_cast<uint8_t>(value);
}

ScalarType ScalarTypeOf(const std::string& name) {
  static const std::map<std::string, ScalarType> types = {
      {"char", ScalarType::kInt8},      {"int8", ScalarType::kInt8},
      {"uchar", ScalarType::kUint8},    {"uint8", ScalarType::kUint8},
      {"short", ScalarType::kInt16},    {"int16", ScalarType::kInt16},
      {"ushort", ScalarType::kUint16},  {"uint16", ScalarType::kUint16},
      {"int", ScalarType::kInt32},      {"int32", ScalarType::kInt32},
      {"uint", ScalarType::kUint32},    {"uint32", ScalarType::kUint32},
      {"float", ScalarType::kFloat32},  {"float32", ScalarType::kFloat32},
      {"double", ScalarType::kFloat64}, {"float64", ScalarType::kFloat64}};
  const auto it = types.find(name);
  return it == types.end() ? ScalarType::kUnknown : it->second;
}

Header ReadHeader(std::istream& in, const std::filesystem::path& file) {
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0)
    Fail("{}: not a PLY file", file.string());
  Header header;
  while (ReadTextLine(in, &line)) {
    std::istringstream s(line);
    std::string keyword;
    s >> keyword;
    if (keyword == "end_header") {
      RequireCountsFit(header, in, file);
      return header;
    }
    if (keyword == "format") {
      std::string format;
      s >> format;
      if (format == "binary_little_endian")
        header.binary = true;
      else if (format != "ascii")
        Fail("{}: PLY format {} is not supported", file.string(), format);
    } else if (keyword == "element") {
      Element e;
      s >> e.name >> e.count;
      header.elements.push_back(e);
    } else if (keyword == "property") {
      if (header.elements.empty()) Fail("{}: PLY property before any element", file.string());
      Property p;
      s >> p.type;
      if (p.type == "list") s >> p.count_type >> p.type;
      s >> p.name;
      p.scalar = ScalarTypeOf(p.type);
      p.count_scalar = ScalarTypeOf(p.count_type);
      header.elements.back().properties.push_back(p);
    }
  }
  Fail("{}: PLY header without end_header", file.string());
}

void RequireKnownTypes(const Element& element, const std::filesystem::path& file) {
  for (const Property& p : element.properties) {
    if (p.IsList() && p.count_scalar == ScalarType::kUnknown)
      Fail("{}: {} list count type {} is not supported", file.string(), element.name, p.count_type);
    if (p.scalar == ScalarType::kUnknown)
      Fail("{}: {} property type {} is not supported", file.string(), element.name, p.type);
  }
}

bool ValueReader::Read(ScalarType type, double* value) {
  if (!binary_) return static_cast<bool>(in_ >> *value);
  char bytes[8];
  if (!in_.read(bytes, static_cast<std::streamsize>(SizeOf(type)))) return false;
  *value = Decode(bytes, type);
  return true;
}

bool ValueReader::ReadBytes(char* bytes, size_t size) {
  return static_cast<bool>(in_.read(bytes, static_cast<std::streamsize>(size)));
}

bool ReadRecord(ValueReader& reader, const Element& element, std::vector<double>* scalars,
                std::vector<std::vector<double>>* lists) {
  const size_t n = element.properties.size();
  scalars->resize(n);
  lists->resize(n);
  const size_t fixed = reader.binary() ? FixedRecordSize(element) : 0;
  if (fixed > 0 && fixed <= kMaxFixedRecord)
    return ReadFixedRecord(reader, element, fixed, scalars);
  for (size_t k = 0; k < n; ++k) {
    const Property& p = element.properties[k];
    if (!p.IsList()) {
      if (!reader.Read(p.scalar, &(*scalars)[k])) return false;
      continue;
    }
    double count;
    // Negated so that NaN fails too; the bound keeps the conversion below defined.
    if (!reader.Read(p.count_scalar, &count) || !(count >= 0 && count < 4294967296.0)) return false;
    // Grown item by item rather than sized from `count`, so a corrupt count ends as truncated
    // data instead of a huge allocation.
    std::vector<double>& list = (*lists)[k];
    list.clear();
    for (size_t j = 0; j < static_cast<size_t>(count); ++j) {
      double item;
      if (!reader.Read(p.scalar, &item)) return false;
      list.push_back(item);
    }
  }
  return true;
}

}  // namespace varsfm::ply
