// Colour images as every command reads them.
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/io/ColourImage.h"

namespace tkgslam {
namespace {

// A JPEG with an EXIF orientation tag.
std::string withExifOrientation(const std::vector<uchar>& jpeg, int orientation) {
  const std::string tiff = std::string("II*\0\x08\0\0\0", 8) +          // little-endian, first IFD at 8
                           std::string("\x01\0", 2) +                    // one entry:
                           std::string("\x12\x01\x03\0\x01\0\0\0", 8) +  // orientation, SHORT, count 1
                           char(orientation) + std::string(3, '\0') +   // its value
                           std::string(4, '\0');                         // no next IFD
  return test::withApp1Segment(std::string(jpeg.begin(), jpeg.end()), std::string("Exif\0\0", 6) + tiff);
}

// A phone photo is stored sideways with a tag saying how to turn it: `detect` and `augment`'s people
// must see it upright, as every image viewer shows it.
TEST(ColourImage, APhotoIsTurnedAsItsExifOrientationSays) {
  test::TempDir tmp;
  cv::Mat image(48, 64, CV_8UC3, cv::Scalar(40, 40, 40));
  image(cv::Rect(0, 0, 16, 16)).setTo(cv::Scalar(255, 255, 255));  // a bright top-left corner
  std::vector<uchar> jpeg;
  cv::imencode(".jpg", image, jpeg);
  test::writeText(tmp / "as_stored.jpg", withExifOrientation(jpeg, 1));
  test::writeText(tmp / "turned.jpg", withExifOrientation(jpeg, 6));  // to be turned 90 degrees clockwise
  const cv::Mat stored = io::readColourImage((tmp / "as_stored.jpg").string());
  ASSERT_EQ(stored.size(), cv::Size(64, 48));
  EXPECT_GT(stored.at<cv::Vec3b>(4, 4)[0], 200);
  const cv::Mat turned = io::readColourImage((tmp / "turned.jpg").string());
  ASSERT_EQ(turned.size(), cv::Size(48, 64));
  EXPECT_GT(turned.at<cv::Vec3b>(4, 43)[0], 200);  // the corner is now at the top right
  EXPECT_LT(turned.at<cv::Vec3b>(4, 4)[0], 100);
}

// A 16-bit image (a depth image given by mistake) is refused, not scaled down to 8 bits.
TEST(ColourImage, ASixteenBitImageIsRefused) {
  test::TempDir tmp;
  cv::imwrite((tmp / "depth.png").string(), cv::Mat(48, 64, CV_16UC1, cv::Scalar(5000)));
  const auto msg = test::inputErrorOf([&] { io::readColourImage((tmp / "depth.png").string(), "RGB image"); });
  EXPECT_NE(msg.find("is not an 8-bit image (a depth image?): it is 16-bit with 1 channel"), std::string::npos) << msg;
}

}  // namespace
}  // namespace tkgslam
