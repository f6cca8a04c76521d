#include <limits>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/io/TumDataset.h"

namespace tkgslam {
namespace {

using test::TempDir;
using test::writeText;

// A tiny valid TUM-layout sequence: 3 frames, JPEG colour, 16-bit depth of 1 m.
void makeDataset(const std::filesystem::path& dir, int w = 64, int h = 48) {
  std::filesystem::create_directories(dir / "rgb");
  std::filesystem::create_directories(dir / "depth");
  std::string rgb = "# color images\n# timestamp filename\n", depth = "# depth\n";
  for (int i = 0; i < 3; ++i) {
    const std::string t = std::to_string(100 + i) + ".000000";
    const std::string td = std::to_string(100 + i) + ".010000";
    cv::imwrite((dir / "rgb" / (t + ".jpg")).string(), cv::Mat(h, w, CV_8UC3, cv::Scalar(10, 20, 30 + i)));
    cv::imwrite((dir / "depth" / (td + ".png")).string(), cv::Mat(h, w, CV_16UC1, cv::Scalar(5000)));
    rgb += t + " rgb/" + t + ".jpg\n";
    depth += td + " depth/" + td + ".png\n";
  }
  writeText(dir / "rgb.txt", rgb);
  writeText(dir / "depth.txt", depth);
}

TEST(TumDataset, ReadsAssociatesAndConvertsDepthToMetres) {
  TempDir tmp;
  makeDataset(tmp.path());
  io::TumDataset ds(tmp.path().string());
  ASSERT_EQ(ds.size(), 3);
  EXPECT_DOUBLE_EQ(ds.timestamp(1), 101.0);
  EXPECT_NEAR(ds.entry(1).depth_timestamp, 101.01, 1e-9);
  const auto f = ds.load(2);
  EXPECT_EQ(f.bgr.type(), CV_8UC3);
  EXPECT_EQ(f.gray.type(), CV_8UC1);
  ASSERT_EQ(f.depth_m.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(f.depth_m.at<float>(10, 10), 1.0f);
  EXPECT_FALSE(ds.groundTruthPath().has_value());
}

TEST(TumDataset, LoopsRepeatTheSequenceWithIncreasingStamps) {
  TempDir tmp;
  makeDataset(tmp.path());
  io::TumDatasetOptions o;
  o.loops = 3;
  io::TumDataset ds(tmp.path().string(), o);
  ASSERT_EQ(ds.size(), 9);
  for (int i = 1; i < 9; ++i) EXPECT_GT(ds.timestamp(i), ds.timestamp(i - 1));
  // More loops than a frame count can hold: refused, not a negative size.
  o.loops = std::numeric_limits<int>::max() / 3 + 1;
  const auto msg = test::inputErrorOf([&] { io::TumDataset(tmp.path().string(), o); });
  EXPECT_NE(msg.find("loops of the 3 frames"), std::string::npos) << msg;
  o.loops = std::numeric_limits<int>::max() / 3;
  EXPECT_EQ(io::TumDataset(tmp.path().string(), o).size(), std::numeric_limits<int>::max() / 3 * 3);
}

TEST(TumDataset, MissingFolder) {
  EXPECT_NE(test::inputErrorOf([] { io::TumDataset("/nonexistent/tkgslam"); }).find("does not exist"), std::string::npos);
}

TEST(TumDataset, MissingList) {
  TempDir tmp;
  makeDataset(tmp.path());
  std::filesystem::remove(tmp / "depth.txt");
  const auto msg = test::inputErrorOf([&] { io::TumDataset(tmp.path().string()); });
  EXPECT_NE(msg.find("depth.txt"), std::string::npos) << msg;
}

TEST(TumDataset, ListedImageAbsent) {
  TempDir tmp;
  makeDataset(tmp.path());
  std::filesystem::remove(tmp.path() / "rgb" / "101.000000.jpg");
  const auto msg = test::inputErrorOf([&] { io::TumDataset(tmp.path().string()); });
  EXPECT_NE(msg.find("101.000000.jpg"), std::string::npos) << msg;
}

TEST(TumDataset, UnreadableImageNamesTheFile) {
  TempDir tmp;
  makeDataset(tmp.path());
  writeText(tmp.path() / "rgb" / "101.000000.jpg", "this is not a jpeg");
  io::TumDataset ds(tmp.path().string());
  EXPECT_NO_THROW(ds.load(0));
  const auto msg = test::inputErrorOf([&] { ds.load(1); });
  EXPECT_NE(msg.find("cannot read RGB image"), std::string::npos) << msg;
  EXPECT_NE(msg.find("101.000000.jpg"), std::string::npos) << msg;
}

// A JPEG cut short decodes with grey rows and only a libjpeg warning: it must be refused as such,
// also when a thumbnail in its header has an end marker of its own, while one with data appended
// after its end marker (some cameras do) is read.
TEST(TumDataset, ATruncatedJpegIsRefusedAndOneWithATrailerRead) {
  TempDir tmp;
  makeDataset(tmp.path());
  cv::Mat noise(48, 64, CV_8UC3);
  cv::randu(noise, 0, 255);
  std::vector<uchar> jpeg;
  cv::imencode(".jpg", noise, jpeg);
  const std::string whole(jpeg.begin(), jpeg.end());
  const std::string with_thumbnail = test::withApp1Segment(whole, "\xFF\xD8 a thumbnail \xFF\xD9");
  writeText(tmp.path() / "rgb" / "100.000000.jpg", with_thumbnail.substr(0, with_thumbnail.size() - 200));
  writeText(tmp.path() / "rgb" / "101.000000.jpg", whole.substr(0, whole.size() / 2));
  writeText(tmp.path() / "rgb" / "102.000000.jpg", with_thumbnail + std::string(3000, 'x'));
  io::TumDataset ds(tmp.path().string());
  for (int i : {0, 1}) {
    const auto msg = test::inputErrorOf([&] { ds.load(i); });
    EXPECT_NE(msg.find(fmt::format("10{}.000000.jpg' is a truncated JPEG", i)), std::string::npos) << msg;
  }
  const cv::Mat read = ds.load(2).bgr;
  ASSERT_EQ(read.size(), noise.size());
  EXPECT_EQ(cv::norm(read, cv::imdecode(jpeg, cv::IMREAD_COLOR), cv::NORM_INF), 0.0);
}

TEST(TumDataset, WrongDepthType) {
  TempDir tmp;
  makeDataset(tmp.path());
  cv::imwrite((tmp.path() / "depth" / "100.010000.png").string(), cv::Mat(48, 64, CV_8UC1, cv::Scalar(3)));
  io::TumDataset ds(tmp.path().string());
  const auto msg = test::inputErrorOf([&] { ds.load(0); });
  EXPECT_NE(msg.find("must be single-channel 16-bit (or 32-bit float metres); it is 8-bit with 1 channel"),
            std::string::npos)
      << msg;
}

TEST(TumDataset, WrongImageSize) {
  TempDir tmp;
  makeDataset(tmp.path());
  io::TumDatasetOptions o;
  o.expected_width = 640;
  o.expected_height = 480;
  // A config for another camera is refused when the sequence is opened ...
  const auto msg = test::inputErrorOf([&] { io::TumDataset(tmp.path().string(), o); });
  EXPECT_NE(msg.find("are 64x48 but the camera config says 640x480"), std::string::npos) << msg;
  // ... and a single frame of another size in the middle is refused when it is loaded.
  o.expected_width = 64;
  o.expected_height = 48;
  cv::imwrite((tmp.path() / "rgb" / "102.000000.jpg").string(), cv::Mat(20, 30, CV_8UC3, cv::Scalar(1, 2, 3)));
  cv::imwrite((tmp.path() / "depth" / "102.010000.png").string(), cv::Mat(20, 30, CV_16UC1, cv::Scalar(1)));
  io::TumDataset ds(tmp.path().string(), o);
  EXPECT_EQ(test::inputErrorOf([&] { ds.load(0); }), "");
  EXPECT_NE(test::inputErrorOf([&] { ds.load(2); }).find("is 30x20 but the camera config says 64x48"), std::string::npos);
  // Depth and colour of different sizes.
  cv::imwrite((tmp.path() / "depth" / "101.010000.png").string(), cv::Mat(10, 10, CV_16UC1, cv::Scalar(1)));
  io::TumDataset ds2(tmp.path().string());
  EXPECT_NE(test::inputErrorOf([&] { ds2.load(1); }).find("is 10x10 but the RGB image is 64x48"), std::string::npos);
}

TEST(TumDataset, NonMonotonicTimestamps) {
  TempDir tmp;
  makeDataset(tmp.path());
  writeText(tmp / "rgb.txt", "101.0 rgb/101.000000.jpg\n100.0 rgb/100.000000.jpg\n");
  const auto msg = test::inputErrorOf([&] { io::TumDataset(tmp.path().string()); });
  EXPECT_NE(msg.find("rgb.txt:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("must increase"), std::string::npos) << msg;
}

TEST(TumDataset, MalformedTimestamp) {
  TempDir tmp;
  makeDataset(tmp.path());
  writeText(tmp / "depth.txt", "# header\n100.01 depth/100.010000.png\n1O1.01 depth/101.010000.png\n");
  const auto msg = test::inputErrorOf([&] { io::TumDataset(tmp.path().string()); });
  EXPECT_NE(msg.find("depth.txt:3: malformed timestamp '1O1.01'"), std::string::npos) << msg;
}

TEST(TumDataset, ListsWithWindowsLineEndsAndAByteOrderMarkAreRead) {
  TempDir tmp;
  makeDataset(tmp.path());
  writeText(tmp / "rgb.txt",
            "\xEF\xBB\xBF# color images\r\n100.000000 rgb/100.000000.jpg\r\n101.000000 rgb/101.000000.jpg\r\n");
  writeText(tmp / "depth.txt", "\xEF\xBB\xBF" "100.010000 depth/100.010000.png\r\n101.010000 depth/101.010000.png\r\n");
  io::TumDataset ds(tmp.path().string());
  ASSERT_EQ(ds.size(), 2u);
  EXPECT_DOUBLE_EQ(ds.entry(0).rgb_timestamp, 100.0);
  EXPECT_EQ(ds.load(1).depth_m.at<float>(0, 0), 1.0f);
}

TEST(TumDataset, MissingFileName) {
  TempDir tmp;
  makeDataset(tmp.path());
  writeText(tmp / "rgb.txt", "100.0\n");
  EXPECT_NE(test::inputErrorOf([&] { io::TumDataset(tmp.path().string()); }).find("rgb.txt:1"), std::string::npos);
}

TEST(TumDataset, EmptyAssociation) {
  TempDir tmp;
  makeDataset(tmp.path());
  writeText(tmp / "depth.txt", "200.0 depth/100.010000.png\n");
  const auto msg = test::inputErrorOf([&] { io::TumDataset(tmp.path().string()); });
  EXPECT_NE(msg.find("no RGB image"), std::string::npos) << msg;
}

// ORB-SLAM2's RGB-D example reads the pairs from an association file (associate.py's output, with
// whichever list it was given first in the first column).
std::string associationText(const io::TumDataset& ds, bool depth_first) {
  std::string text = "# written by associate.py\n";
  for (int i = 0; i < ds.size(); ++i) {
    const auto& e = ds.entry(i);
    const std::string rgb = fmt::format("{:.6f} rgb/{}", e.rgb_timestamp, std::filesystem::path(e.rgb_path).filename().string());
    const std::string depth =
        fmt::format("{:.6f} depth/{}", e.depth_timestamp, std::filesystem::path(e.depth_path).filename().string());
    text += depth_first ? depth + " " + rgb + "\n" : rgb + " " + depth + "\n";
  }
  return text;
}

TEST(TumDataset, AnAssociationFileGivesTheListsPairsInEitherColumnOrder) {
  TempDir tmp;
  makeDataset(tmp.path());
  const io::TumDataset lists(tmp.path().string());
  EXPECT_TRUE(lists.associationFile().empty());
  for (const bool depth_first : {false, true}) {
    SCOPED_TRACE(depth_first ? "depth first" : "rgb first");
    writeText(tmp / "pairs.txt", associationText(lists, depth_first));
    io::TumDatasetOptions o;
    o.associations = (tmp / "pairs.txt").string();
    const io::TumDataset ds(tmp.path().string(), o);
    EXPECT_EQ(ds.associationFile(), o.associations);
    ASSERT_EQ(ds.size(), lists.size());
    for (int i = 0; i < ds.size(); ++i) {
      EXPECT_DOUBLE_EQ(ds.timestamp(i), lists.timestamp(i));
      EXPECT_DOUBLE_EQ(ds.entry(i).depth_timestamp, lists.entry(i).depth_timestamp);
      EXPECT_EQ(ds.entry(i).rgb_path, lists.entry(i).rgb_path);
      EXPECT_EQ(ds.entry(i).depth_path, lists.entry(i).depth_path);
    }
    EXPECT_FLOAT_EQ(ds.load(2).depth_m.at<float>(10, 10), 1.0f);
  }
}

TEST(TumDataset, AssociationFileErrorsNameTheFileAndLine) {
  TempDir tmp;
  makeDataset(tmp.path());
  const auto open = [&](const std::string& text) {
    writeText(tmp / "pairs.txt", text);
    io::TumDatasetOptions o;
    o.associations = (tmp / "pairs.txt").string();
    return test::inputErrorOf([&] { io::TumDataset(tmp.path().string(), o); });
  };
  const std::string l0 = "100.0 rgb/100.000000.jpg 100.01 depth/100.010000.png\n";
  const std::string l1 = "101.0 rgb/101.000000.jpg 101.01 depth/101.010000.png\n";
  std::string msg = open(l0 + "101.0 rgb/101.000000.jpg 101.01\n");
  EXPECT_NE(msg.find("pairs.txt:2: expected 'timestamp filename timestamp filename'"), std::string::npos) << msg;
  msg = open(l0 + "abc rgb/101.000000.jpg 101.01 depth/101.010000.png\n");
  EXPECT_NE(msg.find("pairs.txt:2: malformed timestamp 'abc'"), std::string::npos) << msg;
  msg = open(l1 + l0);
  EXPECT_NE(msg.find("pairs.txt:2: timestamp 100.0 is not after"), std::string::npos) << msg;
  msg = open(l0 + "101.0 rgb/101.000000.jpg 101.01 depth/nowhere.png\n");
  EXPECT_NE(msg.find("pairs.txt:2: image"), std::string::npos) << msg;
  EXPECT_NE(msg.find("nowhere.png' does not exist"), std::string::npos) << msg;
  msg = open("100.0 rgb/100.000000.jpg 101.0 rgb/101.000000.jpg\n");
  EXPECT_NE(msg.find("cannot tell the depth image from the colour one"), std::string::npos) << msg;
  EXPECT_NE(msg.find("neither"), std::string::npos) << msg;
  msg = open("100.01 depth/100.010000.png 101.01 depth/101.010000.png\n");
  EXPECT_NE(msg.find("both"), std::string::npos) << msg;
  // Depth first: the colour timestamps (the frames') must increase too.
  msg = open("100.01 depth/100.010000.png 101.0 rgb/101.000000.jpg\n101.01 depth/101.010000.png 100.0 rgb/100.000000.jpg\n");
  EXPECT_NE(msg.find("pairs.txt:2: colour timestamp 100 is not after"), std::string::npos) << msg;
  msg = open("# nothing\n");
  EXPECT_NE(msg.find("has no entries"), std::string::npos) << msg;
  io::TumDatasetOptions o;
  o.associations = (tmp / "absent.txt").string();
  msg = test::inputErrorOf([&] { io::TumDataset(tmp.path().string(), o); });
  EXPECT_NE(msg.find("absent.txt' does not exist"), std::string::npos) << msg;
  // Without the lists and without an association file, the error says what else would do.
  std::filesystem::remove(tmp / "rgb.txt");
  msg = test::inputErrorOf([&] { io::TumDataset(tmp.path().string()); });
  EXPECT_NE(msg.find("missing image list"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--associations"), std::string::npos) << msg;
}

TEST(TumDataset, RealFr1XyzSequence) {
  TKGSLAM_REQUIRE_SHARED();
  io::TumDataset ds(test::fr1xyz().string());
  EXPECT_GE(ds.size(), 790);  // 798 RGB frames, nearly all with depth within 20 ms
  EXPECT_LE(ds.size(), 798);
  const auto f = ds.load(0);
  EXPECT_EQ(f.bgr.cols, 640);
  EXPECT_EQ(f.bgr.rows, 480);
  // Depth is in metres: the desk scene is between 0.5 m and 4 m away.
  double mn, mx;
  cv::minMaxLoc(f.depth_m, &mn, &mx, nullptr, nullptr, f.depth_m > 0);
  EXPECT_GT(mn, 0.3);
  EXPECT_LT(mx, 6.0);
  EXPECT_TRUE(ds.groundTruthPath().has_value());
}

}  // namespace
}  // namespace tkgslam
