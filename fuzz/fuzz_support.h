#pragma once
// What every harness of fuzz/ shares. The readers under test take file paths, so each input is
// written to a scratch folder of this process first; formats made of several files (a COLMAP
// model, an OBJ with its MTL) come as one input cut into parts at kPartSeparator, so that
// mutations of one part leave the others readable.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace varsfm::fuzz {

// A line of its own between the parts of a multi-file input.
inline constexpr std::string_view kPartSeparator = "\n--varsfm-fuzz-part--\n";

// A folder for this process's files (removed at exit); also silences varsfm's log, whose
// warnings about odd input would otherwise flood the fuzzer's output.
const std::filesystem::path& ScratchDir();

// Writes `size` bytes to `path`, replacing it.
void WriteBytes(const std::filesystem::path& path, const void* data, size_t size);

// `data` cut at each kPartSeparator into exactly `count` parts: missing parts are empty, the
// last part keeps any further separators.
std::vector<std::string> SplitParts(const uint8_t* data, size_t size, size_t count);

// The input cut into one part per file name (SplitParts), each written into the scratch
// folder `folder` (created once): a multi-file model for a reader that takes its folder.
std::filesystem::path WriteParts(const uint8_t* data, size_t size, const std::string& folder,
                                 const std::vector<std::string>& names);

// Parts joined with kPartSeparator: how the seed corpus files are made.
std::string JoinParts(const std::vector<std::string>& parts);

}  // namespace varsfm::fuzz

// libFuzzer's entry point, defined by each harness.
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
