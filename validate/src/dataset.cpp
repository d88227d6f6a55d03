#include "mbest/validate/dataset.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <system_error>

#include "mbest/core/segmentation.h"

namespace mbest::validate {

namespace fs = std::filesystem;

namespace {

// Natural order: runs of digits compare as numbers, so img2 sorts before img10.
bool natural_less(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) &&
        std::isdigit(static_cast<unsigned char>(b[j]))) {
      size_t ie = i, je = j;
      while (ie < a.size() && std::isdigit(static_cast<unsigned char>(a[ie]))) ++ie;
      while (je < b.size() && std::isdigit(static_cast<unsigned char>(b[je]))) ++je;
      const std::string na = a.substr(i, ie - i), nb = b.substr(j, je - j);
      const size_t za = na.find_first_not_of('0'), zb = nb.find_first_not_of('0');
      const std::string ta = za == std::string::npos ? "" : na.substr(za);
      const std::string tb = zb == std::string::npos ? "" : nb.substr(zb);
      if (ta.size() != tb.size()) return ta.size() < tb.size();
      if (ta != tb) return ta < tb;
      if (na.size() != nb.size()) return na.size() < nb.size();
      i = ie, j = je;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

bool is_image_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".png" && ext != ".jpg" && ext != ".jpeg") return false;
  // `mbest detect --out` beside the images writes <stem>.labels.png: a prediction, not an image.
  return p.stem().extension() != ".labels";
}

bool is_dir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

Status list_tier(const fs::path& root, const fs::path& tier_dir, const std::string& tier,
                 bool synthetic, std::vector<DatasetItem>* items) {
  const fs::path images = tier_dir / "images", labels = tier_dir / "labels";
  const fs::path annotations = tier_dir / "annotations";
  if (!is_dir(labels)) return Error{labels.string() + ": missing folder (the ground-truth labels)"};
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::directory_iterator it(images, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file() && is_image_file(it->path())) files.push_back(it->path());
  if (ec) return Error{images.string() + ": cannot list (" + ec.message() + ")"};
  if (files.empty()) return Error{images.string() + ": no .png or .jpg image"};
  std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
    return natural_less(a.stem().string(), b.stem().string());
  });
  for (const fs::path& f : files) {
    DatasetItem item;
    item.tier = tier;
    item.stem = f.stem().string();
    item.image = f.string();
    item.labels = (labels / (item.stem + ".png")).string();
    if (!fs::exists(item.labels)) return Error{item.labels + ": missing label image for " + f.string()};
    if (synthetic) {
      item.annotation = (annotations / (item.stem + ".json")).string();
      if (!fs::exists(item.annotation))
        return Error{item.annotation + ": missing annotation for " + f.string()};
    }
    item.relative_dir = fs::relative(images, root).generic_string();
    items->push_back(std::move(item));
  }
  return ok_status();
}

}  // namespace

Result<Dataset> open_dataset(const std::string& root_arg) {
  const fs::path root(root_arg);
  if (!is_dir(root)) return Error{root_arg + ": not a folder"};
  std::vector<std::pair<std::string, fs::path>> tiers;  // name, folder
  if (is_dir(root / "images")) {
    tiers.emplace_back(fs::weakly_canonical(root).filename().string(), root);
  } else {
    std::error_code ec;
    for (fs::directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec))
      if (is_dir(it->path() / "images")) tiers.emplace_back(it->path().filename().string(), it->path());
    if (ec) return Error{root_arg + ": cannot list (" + ec.message() + ")"};
    std::sort(tiers.begin(), tiers.end(),
              [](const auto& a, const auto& b) { return natural_less(a.first, b.first); });
  }
  if (tiers.empty())
    return Error{root_arg + ": no tier folder (expected " + root_arg +
                 "/<tier>/images and /<tier>/labels)"};
  Dataset d;
  d.root = root_arg;
  d.synthetic = std::all_of(tiers.begin(), tiers.end(),
                            [](const auto& t) { return is_dir(t.second / "annotations"); });
  for (const auto& [name, dir] : tiers) {
    d.tiers.push_back(name);
    if (Status s = list_tier(root, dir, name, d.synthetic, &d.items); !s) return s.error();
  }
  return d;
}

PredictionPaths prediction_paths(const DatasetItem& item, const std::string& pred_dir) {
  const fs::path dir = fs::path(pred_dir) / item.relative_dir;
  return {(dir / (item.stem + ".labels.png")).string(), (dir / (item.stem + ".json")).string()};
}

std::string missing_sibling_mask(const Dataset& dataset, const std::string& name) {
  for (const DatasetItem& item : dataset.items) {
    const std::string path = sibling_mask_path(item.image, name);
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return path;
  }
  return "";
}

}  // namespace mbest::validate
