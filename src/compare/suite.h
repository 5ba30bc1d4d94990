// lray-compare: a suite file, a list of scenes to render and compare with
// their approved images (README.md, "Reference-image CI for your scenes"):
//
//   [defaults]                       # any case key, for every case
//   options = ["-w", "160", "-H", "120"]
//   backends = ["embree", "kdtree"]  # one case per backend: NAME.embree, ...
//
//   [[case]]
//   name = "ring"
//   scene = "scenes/ring.lua"        # paths are relative to the suite file
//   approved = "approved/ring.png"   # PNG, TGA or EXR: the format rendered
//   frame = 2                        # the frame to render (default 0)
//   options = ["-s", "2"]            # lray options, after the defaults'
//   approve_options = []             # added when rendering for --approve
//   metric = "pixel"                 # pixel | psnr | ssim | noise
//   threshold = 0.004                # the metric's bound (comparison.h)
//   allowed = 0.0                    # pixel: % of pixels that may differ
//   second_seed = 7                  # noise, without EXR: a second render
//                                    # at this --seed gives the variance
//   timeout = 600                    # seconds before the render is stopped
//
// A key the format does not know, a value of the wrong type, or a case
// without name, scene or approved is an error naming the file and line.
#pragma once

#include "compare/comparison.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lray::compare {

struct SuiteCase {
  std::string name;
  std::string scene;    ///< absolute or relative to the working directory
  std::string approved; ///< likewise
  int frame = 0;
  std::vector<std::string> options;        ///< lray options, defaults' first
  std::vector<std::string> approveOptions; ///< added for --approve
  Criteria criteria;
  double timeoutSeconds = 600;
  std::optional<int64_t> secondSeed; ///< render again at this --seed (noise test)
};

/// Reads a suite file (TOML); throws CompareError naming the file and line.
std::vector<SuiteCase> readSuite(const std::string &path);

} // namespace lray::compare
