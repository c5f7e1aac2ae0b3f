#pragma once
// The guards of a stage that rewrites a whole output folder (`run`, `map`): before writing its
// model it removes what earlier runs left there (stale dense clouds, meshes, textured models,
// numbered models), which is right in a folder varsfm made and wrong anywhere else -- a user's
// folder of other files, or the photos themselves.
#include <filesystem>
#include <functional>

namespace varsfm {

// Throws varsfm::Error (one line naming `output`) when `output` is a folder that holds files but
// none of the marks of a varsfm output (workspace.db, sparse/, summary.json): the stage would
// delete or overwrite files it did not write. A new or empty folder, or one varsfm wrote, passes.
void CheckOutputFolderIsOurs(const std::filesystem::path& output);

// The stages that write into a varsfm output folder, in the order of the chain.
enum class ChainStage { kMap, kDensify, kMesh, kTexture, kReport };

// Removes from `output` what the stages after `stage` wrote there (densify's cloud, the mesh,
// the textured model, the report): a new result of `stage` makes them stale, and a later stage
// that fails or is not run would leave them beside it for a user or a viewer to take as its
// result. Only in a folder varsfm wrote (the marks of CheckOutputFolderIsOurs); elsewhere
// nothing is removed.
void RemoveOutputsAfter(const std::filesystem::path& output, ChainStage stage);

// Runs `write`, which writes the outputs of `stage` into `output`. When it throws (a full
// disk), every output of `stage` is removed, the old ones too, before the error goes on: a
// stage's outputs are read together (the cloud and its visibility, the OBJ and the glb), and a
// new one beside an old or a missing one would be taken for a pair.
void WriteOutputsTogether(const std::filesystem::path& output, ChainStage stage,
                          const std::function<void()>& write);

// Throws varsfm::Error when `output` is `image_dir` or lies inside it: the photos are listed
// with their subfolders, so a second run would read the first one's texture atlas and renders as
// photos of the scene.
void CheckOutputOutsideImages(const std::filesystem::path& output,
                              const std::filesystem::path& image_dir);

}  // namespace varsfm
