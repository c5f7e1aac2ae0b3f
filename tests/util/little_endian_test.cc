#include "varsfm/util/little_endian.h"

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace varsfm {
namespace {

TEST(LittleEndian, WritesTheLeastSignificantByteFirst) {
  std::ostringstream out;
  PutLittleEndian<uint32_t>(out, 0x01020304u);
  PutLittleEndian<uint16_t>(out, 0xA0B0u);
  PutLittleEndian<uint8_t>(out, 0x7Fu);
  EXPECT_EQ(out.str(), std::string("\x04\x03\x02\x01\xB0\xA0\x7F", 7));
}

TEST(LittleEndian, ReadsBackWhatItWrote) {
  std::ostringstream out;
  PutLittleEndian<double>(out, -1.25e-3);
  PutLittleEndian<int32_t>(out, -7);
  PutLittleEndian<float>(out, 3.5f);
  const std::string bytes = out.str();
  ASSERT_EQ(bytes.size(), 16u);
  EXPECT_EQ(GetLittleEndian<double>(bytes.data()), -1.25e-3);
  EXPECT_EQ(GetLittleEndian<int32_t>(bytes.data() + 8), -7);
  EXPECT_EQ(GetLittleEndian<float>(bytes.data() + 12), 3.5f);
  // IEEE 754 1.0f is 0x3F800000: stored 00 00 80 3F.
  std::ostringstream one;
  PutLittleEndian<float>(one, 1.0f);
  EXPECT_EQ(one.str(), std::string("\x00\x00\x80\x3F", 4));
}

// Appending to a byte string or vector gives the bytes the stream writer gives.
TEST(LittleEndian, AppendsWhatItWouldWrite) {
  std::string text("x");
  AppendLittleEndian<uint32_t>(&text, 0x01020304u);
  AppendLittleEndian<uint16_t>(&text, 0xA0B0u);
  EXPECT_EQ(text, std::string("x\x04\x03\x02\x01\xB0\xA0", 7));
  std::vector<uint8_t> bytes;
  AppendLittleEndian<uint32_t>(&bytes, 0xFF000080u);
  AppendLittleEndian<double>(&bytes, -1.25e-3);
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin(), bytes.begin() + 4),
            (std::vector<uint8_t>{0x80, 0x00, 0x00, 0xFF}));
  ASSERT_EQ(bytes.size(), 12u);
  EXPECT_EQ(GetLittleEndian<double>(reinterpret_cast<const char*>(bytes.data() + 4)), -1.25e-3);
}

}  // namespace
}  // namespace varsfm
