#pragma once
// What a measured run writes for people and tools: the summary and metrics JSON of one row, the
// per-ray files of a traced row, the run's measurements.json and its Google Benchmark JSON.
#include <string>

#include "experiment/plan_runner.hpp"
#include "io/images.hpp"

namespace heightmarch {

struct Provenance;

// The versions of the files' formats (docs/schemas/ holds a JSON Schema of each). A file without
// a format_version field is of version 1: measurements.json then named its measures uv_p95 etc.;
// version 3 added the errors in pixels, the search error against the surface read and the filter's
// bias (metrics.hpp).
inline constexpr int kMeasurementsFormatVersion = 3;
inline constexpr int kMetricsFormatVersion = 3;

// A short human summary of one row, a few lines; speeds as median (min-max).
std::string summary_text(const Measurement& row);

// One row as a JSON object (docs/measures.md's measures, its configuration and provenance):
// what `trace --json` prints and `--out` writes as metrics.json.
std::string metrics_json(const Measurement& row);

// hits.exr, error.png, cost.png (when the sample counts are known), render.png and metrics.json in
// dir (the images in `images`' format: .webp for a suite's gallery), and where the row has an image
// error difference and reference images; for rays from a file, metrics.json and rays.csv (each ray
// with its hit and the exact one) only.
void write_run_outputs(const std::string& dir, const TracedRow& traced,
                       ImageFormat images = ImageFormat::png);

// The run's one table (docs/measurements.md).
std::string measurements_json(const MeasuredPlan& run, const std::string& plan_name);

// The timed rows as Google Benchmark JSON (one iteration entry per repetition, named by
// benchmark_name), for scripts/compare and Google Benchmark's compare.py.
std::string benchmark_json(const MeasuredPlan& run);

}  // namespace heightmarch
