#pragma once
// Writing files so that they appear complete or not at all: the content goes to a hidden
// temporary beside the target, which is renamed onto it only once it is fully written. A run
// that fails or is killed mid-write never leaves a truncated file that a later stage, a viewer
// or another tool would read as valid.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace varsfm {

// Opens a temporary sibling of `file` (binary), calls `write` with it, closes it and renames it
// onto `file`. Throws varsfm::Error naming `file` when the temporary cannot be opened, a write
// failed (the stream's state once `write` returns: disk full, ...) or the rename fails; the
// temporary is removed on any failure, and an exception from `write` is rethrown.
void WriteFileAtomically(const std::filesystem::path& file,
                         const std::function<void(std::ostream& out)>& write);

// `bytes` as the whole content of `file`.
void WriteBytesAtomically(const std::filesystem::path& file, const std::vector<uint8_t>& bytes);

// `json` as the project writes its JSON files (summary.json, ...): indented by 2, a final newline.
void WriteJsonAtomically(const std::filesystem::path& file, const nlohmann::json& json);

// The same for writers that open the file themselves (TinyGLTF, image encoders): `write` is
// given the temporary's path, which ends in the target's extension, and must create that file
// or throw.
void WriteFileViaTemporary(const std::filesystem::path& file,
                           const std::function<void(const std::filesystem::path&)>& write);

// A folder of files written together (a model's cameras/images/points, an OBJ with its
// material and textures): `write` fills a temporary folder beside `dir` with the files `names`;
// only when all exist are they moved into `dir` (the folder is renamed as a whole when `dir`
// does not exist yet, else file by file, leaving other files in `dir` alone). The temporary
// folder is removed on failure. Throws varsfm::Error.
void WriteFilesAtomically(const std::filesystem::path& dir, const std::vector<std::string>& names,
                          const std::function<void(const std::filesystem::path&)>& write);

}  // namespace varsfm
