#pragma once
// Reading the text formats (PLY headers, OBJ and MTL, COLMAP's .txt models) line by line.
#include <istream>
#include <string>

namespace varsfm {

// std::getline without the '\r' of a CRLF line end: files written on Windows read like the
// others.
inline bool ReadTextLine(std::istream& in, std::string* line) {
  if (!std::getline(in, *line)) return false;
  if (!line->empty() && line->back() == '\r') line->pop_back();
  return true;
}

}  // namespace varsfm
