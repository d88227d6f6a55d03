// The data sets `mbest eval` reads, and where a `mbest detect --out DIR` run put its
// prediction for each image.
//   mbest-real: ROOT/<tier>/images/<stem>.jpg, ROOT/<tier>/labels/<stem>.png (8-bit labels)
//   synth:      ROOT/<split>/images/<stem>.png|jpg, labels/<stem>.png (16-bit),
//               annotations/<stem>.json (mbest/synth/annotation.h)
// ROOT may also be a single tier (ROOT/images, ROOT/labels): the tier is named after ROOT.
#pragma once

#include <string>
#include <vector>

#include "mbest/core/result.h"

namespace mbest::validate {

struct DatasetItem {
  std::string tier;          // e.g. "S1", or the split's name
  std::string stem;          // file name without extension, e.g. "img0"
  std::string image;         // path of the colour image
  std::string labels;        // path of the ground-truth label image
  std::string annotation;    // path of the scene's annotation JSON; empty without one
  std::string relative_dir;  // the image's folder relative to ROOT, e.g. "S1/images"
};

struct Dataset {
  std::string root;
  bool synthetic = false;           // every tier has annotations/
  std::vector<std::string> tiers;   // in name order
  std::vector<DatasetItem> items;   // by tier, then stem in natural order (img2 < img10)
};

// Lists the data set at `root`. Errors (missing folder, image without a label file, a synth
// image without its annotation, no image at all) name the path.
Result<Dataset> open_dataset(const std::string& root);

// The first image's mask missing from the sibling folder NAME (mbest/core/segmentation.h,
// sibling_mask_path); empty when every image of `dataset` has one.
std::string missing_sibling_mask(const Dataset& dataset, const std::string& name);

// Where `mbest detect DATASET --out pred_dir` writes the prediction of `item`: its path
// relative to DATASET mirrored under pred_dir, e.g. PRED/S1/images/img0.labels.png and
// PRED/S1/images/img0.json.
struct PredictionPaths {
  std::string labels;
  std::string json;
};
PredictionPaths prediction_paths(const DatasetItem& item, const std::string& pred_dir);

}  // namespace mbest::validate
