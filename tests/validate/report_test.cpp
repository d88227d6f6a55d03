#include "mbest/validate/report.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mbest/validate/dataset.h"
#include "test_data.h"

namespace mbest::validate {
namespace {

using namespace testing;  // NOLINT

std::string read_all(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Tier S1: a perfect image and one finding half; tier S2: a missing prediction.
Evaluation small_evaluation(const fs::path& root, int keep_worst) {
  const cv::Mat gt = two_bars();
  cv::Mat half = gt.clone();
  half.setTo(0, gt == 2);
  add_real_image(root / "data", "S1", "img0", gt);
  add_real_image(root / "data", "S1", "img1", gt);
  add_real_image(root / "data", "S2", "img0", gt);
  add_prediction(root / "pred", "S1", "img0", gt);
  add_prediction(root / "pred", "S1", "img1", half);
  Result<Dataset> d = open_dataset((root / "data").string());
  EvalOptions o;
  o.pred_dir = (root / "pred").string();
  o.keep_worst = keep_worst;
  Result<Evaluation> e = evaluate(d.value(), o);
  EXPECT_TRUE(e.ok());
  return e.value();
}

TEST(Report, TerminalTableHasOneRowPerTierAndAll) {
  const fs::path root = fresh_dir();
  const Evaluation e = small_evaluation(root, 0);
  const std::string t = tier_table(e, summarise(e));
  EXPECT_NE(t.find("strict DICE %"), std::string::npos);
  EXPECT_NE(t.find("S1         2          75.00  25.00      75.00         1         1             1"),
            std::string::npos)
      << t;
  EXPECT_NE(t.find("S2         1           0.00"), std::string::npos) << t;
  EXPECT_NE(t.find("all        3          50.00"), std::string::npos) << t;
  EXPECT_NE(t.find("1 image(s) had no usable prediction"), std::string::npos) << t;
  EXPECT_NE(t.find("e.g. " + (root / "pred" / "S2" / "images" / "img0.labels.png").string() +
                   ": missing prediction"),
            std::string::npos)
      << t;  // the first reason, so that a user need not open report.json to see it
}

TEST(Report, WritesJsonMarkdownAndHtmlWithEveryImage) {
  const fs::path root = fresh_dir();
  const Evaluation e = small_evaluation(root, 2);
  const Summary s = summarise(e);
  const fs::path out = root / "report" / "nested";
  Status st = write_report(e, s, ReportInfo{"mbest eval data --pred pred"}, out.string());
  ASSERT_TRUE(st.ok()) << st.error().message;
  std::vector<std::string> files;
  for (const auto& f : fs::directory_iterator(out)) files.push_back(f.path().filename().string());
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"report.html", "report.json", "report.md"}));

  const nlohmann::json j = nlohmann::json::parse(read_all(out / "report.json"));
  EXPECT_EQ(j["command"], "mbest eval data --pred pred");
  EXPECT_EQ(j["layout"], "mbest-real");
  ASSERT_EQ(j["tiers"].size(), 2u);
  EXPECT_DOUBLE_EQ(j["tiers"][0]["strict_dice_pct"].get<double>(), 75.0);
  EXPECT_EQ(j["tiers"][0]["below_95"], 1);
  EXPECT_EQ(j["tiers"][1]["missing_predictions"], 1);
  ASSERT_EQ(j["images"].size(), 3u);
  EXPECT_EQ(j["images"][1]["stem"], "img1");
  EXPECT_DOUBLE_EQ(j["images"][1]["strict"].get<double>(), 0.5);
  EXPECT_EQ(j["images"][1]["instances"].size(), 2u);

  const std::string md = read_all(out / "report.md");
  EXPECT_NE(md.find("| S1 | 2 | 75.00 | 25.00 | 75.00 | 1 | 1 | 1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| S2/img0 | 0.00 |"), std::string::npos) << md;

  const std::string html = read_all(out / "report.html");
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("</html>"), std::string::npos);
  EXPECT_NE(html.find("data:image/png;base64,iVBORw0KGgo"), std::string::npos);  // a PNG chart
  // The gallery: the two worst images, each an inlined JPEG.
  size_t jpegs = 0;
  for (size_t at = html.find("data:image/jpeg;base64,/9j/"); at != std::string::npos;
       at = html.find("data:image/jpeg;base64,/9j/", at + 1))
    ++jpegs;
  EXPECT_EQ(jpegs, 2u);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);  // self-contained
}

TEST(Report, RewritingReplacesTheReport) {
  const fs::path root = fresh_dir();
  const Evaluation e = small_evaluation(root, 0);
  write_text(root / "report" / "report.md", "old");
  ASSERT_TRUE(write_report(e, summarise(e), {}, (root / "report").string()).ok());
  EXPECT_NE(read_all(root / "report" / "report.md"), "old");
}

TEST(Report, UnwritableFolderIsAnErrorNamingIt) {
  const fs::path root = fresh_dir();
  const Evaluation e = small_evaluation(root, 0);
  write_text(root / "taken", "a file where the folder should be");
  Status st = write_report(e, summarise(e), {}, (root / "taken").string());
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("taken"), std::string::npos);
  fs::create_directories(root / "dir" / "report.json");  // a folder where a file should be
  Status blocked = write_report(e, summarise(e), {}, (root / "dir").string());
  ASSERT_FALSE(blocked.ok());
  EXPECT_NE(blocked.error().message.find("report.json"), std::string::npos);
  for (const auto& f : fs::directory_iterator(root / "dir"))
    EXPECT_EQ(f.path().filename().string().find(".tmp"), std::string::npos) << f.path();
}

TEST(Report, SyntheticReportHasCrossingTablesAndBins) {
  const fs::path root = fresh_dir();
  const cv::Mat gt = add_synth_scene(root / "data", "s2", "000000");
  add_prediction(root / "pred", "s2", "000000", gt);
  // The detector's list: the crossing, rod 1 (label 1) on top, 2.5 degrees off, and a
  // spurious one.
  write_text(root / "pred" / "s2" / "images" / "000000.json", R"({"dlos": [], "crossings": [
      {"location": [50, 41], "angle_deg": 62.5, "dlos_top_first": [1, 2]},
      {"location": [90, 40], "angle_deg": 30, "dlos_top_first": [1, 2]}]})");
  Result<Dataset> d = open_dataset((root / "data").string());
  EvalOptions o;
  o.pred_dir = (root / "pred").string();
  Result<Evaluation> e = evaluate(d.value(), o);
  ASSERT_TRUE(e.ok());
  const Summary s = summarise(e.value());
  const std::string md = report_markdown(e.value(), s, {});
  EXPECT_NE(md.find("| 45-90 | 100.00 | 1 | 100.00 | 1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("total_turning_rad"), std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(report_json(e.value(), s, {}));
  EXPECT_EQ(j["layout"], "synth");
  EXPECT_EQ(j["pairing_by_angle"][3]["correct"], 1);
  // Per tier too: the accuracy goal is stated per angle, and presets differ widely.
  EXPECT_NE(md.find("| s2 | - | - | - | 100.00 (1) |"), std::string::npos) << md;
  EXPECT_EQ(j["tiers"][0]["crossings"]["pairing_by_angle"][3]["assessed"], 1);
  EXPECT_EQ(j["tiers"][0]["crossings"]["pairing_by_angle"][0]["assessed"], 0);
  EXPECT_EQ(j["images"][0]["crossings"][0]["pairing_correct"], true);
  EXPECT_TRUE(j["images"][0]["crossings"][0]["pairing_failure"].is_null());
  EXPECT_NE(md.find("| s2 | - | - | - | - | - |"), std::string::npos) << md;  // no failures
  const std::string t = tier_table(e.value(), s);
  EXPECT_NE(t.find("pairing %"), std::string::npos) << t;

  // The detector's crossing list, labelled as a figure beyond metrics.md.
  EXPECT_NE(md.find("## Detected crossings per tier"), std::string::npos) << md;
  EXPECT_NE(md.find("| s2 | 1 | 1 | 2 | 1 | 100.00 | 50.00 | 0 | 0.00 | 100.00 | 1 | 2.50 |"),
            std::string::npos)
      << md;
  const std::string definitions = md.substr(md.find("## Definitions"));
  EXPECT_NE(definitions.find("Detected crossings, a figure beyond ../shared/docs/metrics.md"),
            std::string::npos)
      << definitions;
  const nlohmann::json& tier = j["tiers"][0]["detected_crossings"];
  EXPECT_EQ(tier["gt"], 1);
  EXPECT_EQ(tier["detected"], 2);
  EXPECT_EQ(tier["matched"], 1);
  EXPECT_DOUBLE_EQ(tier["recall_pct"].get<double>(), 100.0);
  EXPECT_DOUBLE_EQ(tier["precision_pct"].get<double>(), 50.0);
  EXPECT_EQ(tier["count_equal"], 0);
  EXPECT_DOUBLE_EQ(tier["top_correct_pct"].get<double>(), 100.0);
  EXPECT_DOUBLE_EQ(tier["angle_error_median_deg"].get<double>(), 2.5);
  const nlohmann::json& image = j["images"][0]["detected_crossings"];
  EXPECT_EQ(image["count_equal"], false);
  ASSERT_EQ(image["matches"].size(), 1u);
  EXPECT_EQ(image["matches"][0]["detected"], 0);
  EXPECT_EQ(image["matches"][0]["top_correct"], true);
  const std::string html = report_html(e.value(), s, {});
  EXPECT_NE(html.find("<h2>Detected crossings per tier</h2>"), std::string::npos);
  EXPECT_NE(html.find("<td>s2</td><td class=num>1</td><td class=num>1</td><td class=num>2</td>"
                      "<td class=num>1</td><td class=num>100.00</td><td class=num>50.00</td>"),
            std::string::npos);
}

TEST(Report, PairingFailuresAreCountedByCauseAndMarkedOnEachCrossing) {
  // Two failures at 20-45 degrees, one local and one where a rod (DICE 0.6) is split.
  const Evaluation e = one_scored_image({{1, 0.99}, {2, 0.98}, {3, 0.6}},
                                        {scored_crossing(1, 2, 30, true, false),
                                         scored_crossing(1, 3, 30, true, false)});
  const Summary s = summarise(e);
  const std::string md = report_markdown(e, s, {});
  EXPECT_NE(md.find("## Pairing failures by cause"), std::string::npos) << md;
  EXPECT_NE(md.find("| s3 | - | - | 1 + 1 | - | 1 + 1 |"), std::string::npos) << md;
  const nlohmann::json j = nlohmann::json::parse(report_json(e, s, {}));
  EXPECT_EQ(j["images"][0]["crossings"][0]["pairing_failure"], "local");
  EXPECT_EQ(j["images"][0]["crossings"][1]["pairing_failure"], "rod_split_or_merged");
  const nlohmann::json& bin = j["tiers"][0]["crossings"]["pairing_failures_by_angle"][2];
  EXPECT_EQ(bin["bin"], "20-45");
  EXPECT_EQ(bin["local"], 1);
  EXPECT_EQ(bin["rod_split_or_merged"], 1);
  EXPECT_NE(report_html(e, s, {}).find("<h3>Pairing failures by cause"), std::string::npos);
}

TEST(Report, PairingByCrowdingListsOnlyBinsWithCrossings) {
  CrossingResolution lone = scored_crossing(1, 2, 30, true, true);
  CrossingResolution crowded = scored_crossing(1, 3, 12, true, false);
  crowded.neighbours = 5;
  const Evaluation e = one_scored_image({{1, 0.99}, {2, 0.98}, {3, 0.99}}, {lone, crowded});
  const Summary s = summarise(e);
  const std::string md = report_markdown(e, s, {});
  const size_t at = md.find("## Pairing % by crowding, per tier");
  ASSERT_NE(at, std::string::npos) << md;
  const std::string table = md.substr(at, md.find("\n## ", at + 1) - at);
  EXPECT_NE(table.find("| s3 | 0 | - | 100.00 (1) |"), std::string::npos) << table;
  EXPECT_NE(table.find("| s3 | 4+ | 0.00 (1) | - |"), std::string::npos) << table;
  EXPECT_EQ(table.find("| s3 | 1 |"), std::string::npos) << table;  // empty bins left out
  EXPECT_EQ(table.find("| s3 | 2-3 |"), std::string::npos) << table;
  const nlohmann::json j = nlohmann::json::parse(report_json(e, s, {}));
  const nlohmann::json& c = j["tiers"][0]["crossings"]["pairing_by_crowding"];
  EXPECT_EQ(c["from_20_deg"][0]["correct"], 1);
  EXPECT_EQ(c["under_20_deg"][3]["assessed"], 1);
  EXPECT_EQ(j["images"][0]["crossings"][1]["neighbours"], 5);
  EXPECT_NE(report_html(e, s, {}).find("<h3>Pairing % by crowding, per tier</h3>"),
            std::string::npos);
}

TEST(Report, FailedCrossingsAreListedAndShownCloseUp) {
  const fs::path root = fresh_dir();
  for (int i = 0; i < 3; ++i) {
    const std::string stem = "00000" + std::to_string(i);
    const cv::Mat gt = add_synth_scene(root / "data", "s2", stem);
    add_prediction(root / "pred", "s2", stem, i == 0 ? gt : switched_at_the_crossing(gt));
  }
  Result<Dataset> d = open_dataset((root / "data").string());
  EvalOptions o;
  o.pred_dir = (root / "pred").string();
  o.keep_failed_crossings = 1;
  Result<Evaluation> e = evaluate(d.value(), o);
  ASSERT_TRUE(e.ok());
  const Summary s = summarise(e.value());
  const std::string md = report_markdown(e.value(), s, {});
  EXPECT_NE(md.find("## Failed crossings"), std::string::npos) << md;
  EXPECT_NE(md.find("| s2 | 45-90 | s2/images/000001 | 0 | 60.0 | 50, 40 | 1, 2 | a rod of the "
                    "crossing split, merged or missed |"),
            std::string::npos)
      << md;
  EXPECT_EQ(md.find("000002 | 0 | 60.0"), std::string::npos) << md;  // one per tier and bin
  const std::string html = report_html(e.value(), s, {});
  const size_t section = html.find("<h2>Failed crossings</h2>");
  ASSERT_NE(section, std::string::npos);
  EXPECT_NE(html.find("<h3>s2, 45-90 degrees</h3>", section), std::string::npos);
  EXPECT_NE(html.find("data:image/jpeg;base64,", section), std::string::npos);
  EXPECT_NE(html.find("s2/images/000001, crossing 0: 60.0 degrees, rods 1 and 2", section),
            std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(report_json(e.value(), s, {}));
  EXPECT_EQ(j["images"][1]["crossings"][0]["location"], nlohmann::json::array({50.0, 40.0}));

  // Without the option (or on real data) there is no such section.
  o.keep_failed_crossings = 0;
  Result<Evaluation> plain = evaluate(d.value(), o);
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(report_markdown(plain.value(), summarise(plain.value()), {}).find("Failed crossings"),
            std::string::npos);
}

TEST(Report, RealDataHasNoDetectedCrossings) {
  const Evaluation e = small_evaluation(fresh_dir(), 0);
  const Summary s = summarise(e);
  EXPECT_EQ(report_markdown(e, s, {}).find("Detected crossings"), std::string::npos);
  EXPECT_FALSE(nlohmann::json::parse(report_json(e, s, {}))["all"].contains("detected_crossings"));
}

}  // namespace
}  // namespace mbest::validate
