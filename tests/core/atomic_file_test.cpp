#include "mbest/core/atomic_file.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <sys/stat.h>
#include <unistd.h>

namespace mbest {
namespace {

namespace fs = std::filesystem;

std::string read_all(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The names in `dir`, sorted.
std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mbest_atomic_file_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

TEST_F(AtomicFile, TemporaryNameIsHiddenBesideTheTargetAndKeepsTheExtension) {
  EXPECT_EQ(temporary_path_for("out/000003.jpg"), "out/.000003.tmp.jpg");
  EXPECT_EQ(temporary_path_for("out/a.labels.png"), "out/.a.labels.tmp.png");
  EXPECT_EQ(temporary_path_for("report.json"), ".report.tmp.json");
  EXPECT_EQ(temporary_path_for("out/README"), "out/.README.tmp");
}

TEST_F(AtomicFile, WritesBytesAndLeavesOnlyTheTarget) {
  const std::string text("line\n\0binary", 12);
  ASSERT_TRUE(write_file_atomically(path("a.txt"), text));
  EXPECT_EQ(read_all(path("a.txt")), text);
  const std::vector<uchar> bytes = {0, 1, 2, 255};
  ASSERT_TRUE(write_file_atomically(path("b.bin"), bytes));
  EXPECT_EQ(read_all(path("b.bin")), std::string("\0\1\2\xff", 4));
  ASSERT_TRUE(write_file_atomically(path("empty"), std::string()));
  EXPECT_TRUE(fs::is_regular_file(path("empty")));
  EXPECT_EQ(fs::file_size(path("empty")), 0u);
  EXPECT_EQ(names_in(dir_), (std::vector<std::string>{"a.txt", "b.bin", "empty"}));
}

TEST_F(AtomicFile, ReplacesAnExistingFile) {
  std::ofstream(path("a.json")) << "a much longer old content than the new one";
  ASSERT_TRUE(write_file_atomically(path("a.json"), "{}"));
  EXPECT_EQ(read_all(path("a.json")), "{}");
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"a.json"});
}

TEST_F(AtomicFile, ReplacesATemporaryLeftByAnInterruptedWrite) {
  std::ofstream(temporary_path_for(path("a.jpg"))) << "partial";
  cv::Mat image(8, 8, CV_8UC3, cv::Scalar(10, 20, 30));
  ASSERT_TRUE(write_image_atomically(path("a.jpg"), image));
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"a.jpg"});
}

TEST_F(AtomicFile, WritesImagesInTheFormatOfTheExtension) {
  cv::Mat labels(5, 7, CV_16UC1);
  for (int y = 0; y < labels.rows; ++y)
    for (int x = 0; x < labels.cols; ++x) labels.at<ushort>(y, x) = static_cast<ushort>(1000 * y + x);
  ASSERT_TRUE(write_image_atomically(path("labels.png"), labels, {cv::IMWRITE_PNG_COMPRESSION, 1}));
  const cv::Mat back = cv::imread(path("labels.png"), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(back.type(), CV_16UC1);
  EXPECT_EQ(cv::countNonZero(back != labels), 0);

  const cv::Mat picture(16, 24, CV_8UC3, cv::Scalar(40, 80, 120));
  ASSERT_TRUE(write_image_atomically(path("picture.jpg"), picture, {cv::IMWRITE_JPEG_QUALITY, 90}));
  EXPECT_EQ(read_all(path("picture.jpg")).substr(0, 3), "\xff\xd8\xff");  // JPEG magic
  EXPECT_EQ(cv::imread(path("picture.jpg")).size(), picture.size());
  EXPECT_EQ(names_in(dir_), (std::vector<std::string>{"labels.png", "picture.jpg"}));
}

TEST_F(AtomicFile, AnImageThatCannotBeEncodedIsAnErrorNamingThePath) {
  const cv::Mat image(4, 4, CV_8UC1, cv::Scalar(0));
  const Status unknown = write_image_atomically(path("a.nosuchformat"), image);
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().message.find(path("a.nosuchformat")), std::string::npos) << unknown.error().message;
  const Status empty = write_image_atomically(path("b.png"), cv::Mat());
  ASSERT_FALSE(empty);
  EXPECT_NE(empty.error().message.find(path("b.png")), std::string::npos) << empty.error().message;
  EXPECT_TRUE(names_in(dir_).empty());
}

TEST_F(AtomicFile, MissingFolderIsAnErrorNamingThePathAndTheReason) {
  const std::string target = path("missing/a.txt");
  const Status s = write_file_atomically(target, "x");
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find(target), std::string::npos) << s.error().message;
  EXPECT_NE(s.error().message.find("No such file or directory"), std::string::npos) << s.error().message;
  EXPECT_TRUE(names_in(dir_).empty());

  std::ofstream(path("file")) << "a file where the folder should be";
  const Status blocked = write_image_atomically(path("file/a.png"), cv::Mat(4, 4, CV_8UC1, cv::Scalar(7)));
  ASSERT_FALSE(blocked);
  EXPECT_NE(blocked.error().message.find(path("file/a.png")), std::string::npos) << blocked.error().message;
  EXPECT_NE(blocked.error().message.find("Not a directory"), std::string::npos) << blocked.error().message;
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"file"});
}

TEST_F(AtomicFile, AFolderInTheWayIsAnErrorAndLeavesNoTemporary) {
  // The temporary file is written, then the rename onto the folder fails.
  fs::create_directories(path("a.png"));
  const Status s = write_image_atomically(path("a.png"), cv::Mat(4, 4, CV_8UC1, cv::Scalar(7)));
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find(path("a.png")), std::string::npos) << s.error().message;
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"a.png"});
  EXPECT_TRUE(fs::is_empty(path("a.png")));
}

TEST_F(AtomicFile, UnwritableFolderIsAnErrorAndLeavesNoTemporary) {
  if (::geteuid() == 0) GTEST_SKIP() << "root can write to a read-only folder";
  fs::create_directories(path("ro"));
  fs::permissions(path("ro"), fs::perms::owner_read | fs::perms::owner_exec);
  const Status s = write_file_atomically(path("ro/a.txt"), "x");
  fs::permissions(path("ro"), fs::perms::owner_all);
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find(path("ro/a.txt")), std::string::npos) << s.error().message;
  EXPECT_NE(s.error().message.find("Permission denied"), std::string::npos) << s.error().message;
  EXPECT_TRUE(names_in(path("ro")).empty());
}

}  // namespace
}  // namespace mbest
