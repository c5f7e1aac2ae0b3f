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
double Decode(const char* bytes, const std::string& type) {
  auto as = [&]<typename T>(T) { return static_cast<double>(GetLittleEndian<T>(bytes)); };
  if (type == "char" || type == "int8") return as(int8_t{});
  if (type == "uchar" || type == "uint8") return as(uint8_t{});
  if (type == "short" || type == "int16") return as(int16_t{});
  if (type == "ushort" || type == "uint16") return as(uint16_t{});
  if (type == "int" || type == "int32") return as(int32_t{});
  if (type == "uint" || type == "uint32") return as(uint32_t{});
  if (type == "float" || type == "float32") return as(float{});
  return as(double{});
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
          header.binary ? std::max<size_t>(TypeSize(p.IsList() ? p.count_type : p.type), 1) : 1;
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

size_t TypeSize(const std::string& type) {
  static const std::map<std::string, size_t> sizes = {
      {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
      {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  const auto it = sizes.find(type);
  return it == sizes.end() ? 0 : it->second;
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
      p.size = TypeSize(p.type);
      header.elements.back().properties.push_back(p);
    }
  }
  Fail("{}: PLY header without end_header", file.string());
}

void RequireKnownTypes(const Element& element, const std::filesystem::path& file) {
  for (const Property& p : element.properties) {
    if (p.IsList() && TypeSize(p.count_type) == 0)
      Fail("{}: {} list count type {} is not supported", file.string(), element.name, p.count_type);
    if (p.size == 0)
      Fail("{}: {} property type {} is not supported", file.string(), element.name, p.type);
  }
}

bool ValueReader::Read(const std::string& type, double* value) {
  if (!binary_) return static_cast<bool>(in_ >> *value);
  char bytes[8];
  if (!in_.read(bytes, static_cast<std::streamsize>(TypeSize(type)))) return false;
  *value = Decode(bytes, type);
  return true;
}

bool ReadRecord(ValueReader& reader, const Element& element, std::vector<double>* scalars,
                std::vector<std::vector<double>>* lists) {
  const size_t n = element.properties.size();
  scalars->resize(n);
  lists->resize(n);
  for (size_t k = 0; k < n; ++k) {
    const Property& p = element.properties[k];
    if (!p.IsList()) {
      if (!reader.Read(p.type, &(*scalars)[k])) return false;
      continue;
    }
    double count;
    // Negated so that NaN fails too; the bound keeps the conversion below defined.
    if (!reader.Read(p.count_type, &count) || !(count >= 0 && count < 4294967296.0)) return false;
    // Grown item by item rather than sized from `count`, so a corrupt count ends as truncated
    // data instead of a huge allocation.
    std::vector<double>& list = (*lists)[k];
    list.clear();
    for (size_t j = 0; j < static_cast<size_t>(count); ++j) {
      double item;
      if (!reader.Read(p.type, &item)) return false;
      list.push_back(item);
    }
  }
  return true;
}

}  // namespace varsfm::ply
