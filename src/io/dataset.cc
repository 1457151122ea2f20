// Dataset::Open: detects the layout of a folder and hands it to the YCB-Video or BOP reader.
#include "mcpose/dataset.h"

#include <exception>
#include <filesystem>

#include "io/bop_dataset.h"
#include "io/ycbv_dataset.h"

namespace mcpose {

StatusOr<std::unique_ptr<Dataset>> Dataset::Open(const std::string& root, const std::string& split,
                                                 const std::string& models_dir) {
  namespace fs = std::filesystem;
  try {
    std::error_code ec;
    if (!fs::exists(root, ec)) return NotFound(root + ": dataset folder does not exist");
    if (!fs::is_directory(root, ec)) return InvalidArgument(root + ": is not a folder");
    if (!models_dir.empty() && !fs::is_directory(models_dir, ec))
      return NotFound(models_dir + ": models folder does not exist");
    const std::string models = models_dir.empty() ? root + "/models" : models_dir;

    const bool has_classes = fs::is_regular_file(root + "/classes.txt", ec);
    const bool has_data = fs::is_directory(root + "/data", ec);
    if (has_classes && has_data) return io::OpenYcbvDataset(root, models);

    const bool has_models_info = fs::is_regular_file(root + "/models/models_info.json", ec);
    const bool has_split = !split.empty() && fs::is_directory(root + "/" + split, ec);
    if (has_models_info && has_split) return io::OpenBopDataset(root, split, models);

    // Neither: say what is missing for the layout the folder resembles most.
    if (has_models_info) {
      return NotFound(root + ": BOP dataset has no split folder '" + split + "'");
    }
    if (has_classes || has_data) {
      return NotFound(root + ": YCB-Video dataset is missing " +
                      (has_classes ? "the data/ folder" : "classes.txt"));
    }
    return InvalidArgument(root +
                           ": not a dataset folder: YCB-Video needs classes.txt and data/, BOP "
                           "needs models/models_info.json and a '" + split + "' folder");
  } catch (const std::exception& e) {
    return Internal(root + ": cannot open dataset (" + e.what() + ")");
  }
}

}  // namespace mcpose
