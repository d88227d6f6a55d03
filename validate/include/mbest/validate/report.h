// The reports of `mbest eval`: a table for the terminal, and report.json (every figure, every
// image), report.md (tables) and a self-contained report.html (charts, worst-image gallery).
#pragma once

#include <string>

#include "mbest/core/result.h"
#include "mbest/validate/evaluation.h"
#include "mbest/validate/summary.h"

namespace mbest::validate {

struct ReportInfo {
  std::string command;  // the command line that produced the evaluation, quoted in reports
};

// Per-tier table (tier, images, strict DICE %, std, lenient %, below 90, below 95, count
// errors), then for synthetic data crossing resolution and centerline error per tier.
std::string tier_table(const Evaluation& evaluation, const Summary& summary);

// Every figure of the summary and of every image, as JSON text.
std::string report_json(const Evaluation& evaluation, const Summary& summary,
                        const ReportInfo& info);

// Tables in Markdown: per tier, per bin, the worst images.
std::string report_markdown(const Evaluation& evaluation, const Summary& summary,
                            const ReportInfo& info);

// One HTML page with everything inlined: tables, charts (PNG drawn with Cairo, base64) and a
// gallery of the worst images (those whose predictions evaluate() kept) with overlays of the
// prediction against the ground truth.
std::string report_html(const Evaluation& evaluation, const Summary& summary,
                        const ReportInfo& info);

// Writes report.json, report.md and report.html into `dir` (created if missing), each under
// a temporary name first, then renamed. Errors name the file.
Status write_report(const Evaluation& evaluation, const Summary& summary,
                    const ReportInfo& info, const std::string& dir);

}  // namespace mbest::validate
