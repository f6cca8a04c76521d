#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/data/MapPoint.h"
#include "tkgslam/feature/OrbExtractor.h"

namespace tkgslam {
namespace {

cv::Mat firstImage() {
  return cv::imread((test::fr1xyz() / "rgb" / "1305031102.175304.jpg").string(), cv::IMREAD_GRAYSCALE);
}

TEST(OrbExtractor, ExtractsAboutTheRequestedNumberSpreadOverImageAndLevels) {
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat img = firstImage();
  ASSERT_FALSE(img.empty());
  feature::OrbExtractor ex(feature::OrbParams{});
  const auto f = ex.extract(img);
  EXPECT_GE(f.keypoints.size(), 900u);
  EXPECT_LE(f.keypoints.size(), 1100u);
  ASSERT_EQ(f.descriptors.rows, int(f.keypoints.size()));
  EXPECT_EQ(f.descriptors.cols, 32);
  // Every level contributes, finer levels more.
  std::vector<int> per_level(8, 0);
  for (const auto& kp : f.keypoints) per_level[kp.octave]++;
  for (int l = 0; l < 8; ++l) EXPECT_GT(per_level[l], 20) << "level " << l;
  EXPECT_GT(per_level[0], per_level[7]);
  // The quadtree spreads them: each quarter of the image holds at least 10 %.
  int quarter[4] = {0, 0, 0, 0};
  for (const auto& kp : f.keypoints) quarter[(kp.pt.x > 320) + 2 * (kp.pt.y > 240)]++;
  for (int q : quarter) EXPECT_GT(q, int(f.keypoints.size()) / 10);
}

TEST(OrbExtractor, DescriptorsAreRotationInvariantAndDeterministic) {
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat img = firstImage();
  feature::OrbExtractor ex(feature::OrbParams{});
  const auto a = ex.extract(img);
  const auto b = ex.extract(img);
  ASSERT_EQ(a.keypoints.size(), b.keypoints.size());
  EXPECT_EQ(cv::norm(a.descriptors, b.descriptors, cv::NORM_HAMMING), 0.0);
  // Rotate the image by 90 degrees: most keypoints must find their counterpart by descriptor.
  cv::Mat rotated;
  cv::rotate(img, rotated, cv::ROTATE_90_CLOCKWISE);
  const auto r = ex.extract(rotated);
  int good = 0, tested = 0;
  for (size_t i = 0; i < a.keypoints.size(); i += 5) {
    ++tested;
    int best = 256;
    size_t best_j = 0;
    for (size_t j = 0; j < r.keypoints.size(); ++j) {
      const int d = data::descriptorDistance(a.descriptors.row(int(i)), r.descriptors.row(int(j)));
      if (d < best) best = d, best_j = j;
    }
    // (x, y) -> (H - 1 - y, x) under a clockwise rotation.
    const cv::Point2f expect(float(img.rows - 1) - a.keypoints[i].pt.y, a.keypoints[i].pt.x);
    if (best < 50 && cv::norm(r.keypoints[best_j].pt - expect) < 3.0 * (1 << (a.keypoints[i].octave / 2))) ++good;
  }
  EXPECT_GT(good, tested * 0.4) << good << " of " << tested;
}

// OpenCV's ORB, given the whole image and the keypoints at their octaves, gives the same bits.
void expectOpenCvsDescriptorsOnTheWholeImage(const cv::Mat& img, const feature::OrbParams& params,
                                             const feature::OrbFeatures& f) {
  auto orb = cv::ORB::create(params.features, float(params.scale_factor), params.levels, 16, 0, 2,
                             cv::ORB::FAST_SCORE, 31, params.fast_threshold);
  std::vector<cv::KeyPoint> kps = f.keypoints;
  cv::Mat expected;
  orb->compute(img, kps, expected);
  ASSERT_EQ(kps.size(), f.keypoints.size());
  ASSERT_EQ(expected.size(), f.descriptors.size());
  int differing = 0;
  for (int i = 0; i < expected.rows; ++i) differing += cv::norm(expected.row(i), f.descriptors.row(i), cv::NORM_HAMMING) > 0;
  EXPECT_EQ(differing, 0) << "of " << expected.rows;
}

TEST(OrbExtractor, DescriptorsAreOpenCvsOrbOnTheFullImageAtEachKeypointsOctave) {
  // The extractor describes each level's keypoints on the level image it already has; OpenCV's
  // ORB given the full image builds its own pyramid for that. Both must give the same bits.
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat img = firstImage();
  const feature::OrbParams params;
  feature::OrbExtractor ex(params);
  const auto f = ex.extract(img);
  expectOpenCvsDescriptorsOnTheWholeImage(img, params, f);
}

TEST(OrbExtractor, KeypointsInPartOfTheImageGetTheWholeImagesDescriptors) {
  // Each level's keypoints are described on the part of the level around them: the free window
  // in the middle leaves that part's edges inside the image on every side.
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat img = firstImage();
  const feature::OrbParams params;
  feature::OrbExtractor ex(params);
  cv::Mat skip(img.size(), CV_8U, cv::Scalar(255));
  skip(cv::Rect(160, 120, 320, 240)).setTo(0);
  const auto f = ex.extract(img, skip);
  ASSERT_GT(f.keypoints.size(), 100u);
  expectOpenCvsDescriptorsOnTheWholeImage(img, params, f);
}

TEST(OrbExtractor, ASkipMaskSendsTheWholeBudgetElsewhere) {
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat img = firstImage();
  ASSERT_FALSE(img.empty());
  feature::OrbExtractor ex(feature::OrbParams{});
  // A person-sized box over the left 70 % of the image.
  cv::Mat skip = cv::Mat::zeros(img.size(), CV_8U);
  skip(cv::Rect(0, 0, 448, 480)).setTo(255);
  const auto all = ex.extract(img);
  const auto rest = ex.extract(img, skip);
  int before = 0;
  for (const auto& kp : all.keypoints) before += kp.pt.x >= 448.5f;
  for (const auto& kp : rest.keypoints) EXPECT_GE(kp.pt.x, 447.5f);
  ASSERT_EQ(rest.descriptors.rows, int(rest.keypoints.size()));
  // The free 30 % holds about a third of the keypoints without the mask; with it, well over
  // twice that (every level still fills its quota where it can).
  EXPECT_GT(int(rest.keypoints.size()), 2 * before) << before << " -> " << rest.keypoints.size();
  // Those it kept anyway are the same keypoints with the same descriptors.
  int same = 0;
  for (size_t i = 0; i < rest.keypoints.size(); ++i) {
    for (size_t j = 0; j < all.keypoints.size(); ++j) {
      if (all.keypoints[j].pt == rest.keypoints[i].pt && all.keypoints[j].octave == rest.keypoints[i].octave) {
        same += cv::norm(all.descriptors.row(int(j)), rest.descriptors.row(int(i)), cv::NORM_HAMMING) == 0;
        break;
      }
    }
  }
  EXPECT_GT(same, before / 2);
  EXPECT_THROW(ex.extract(img, cv::Mat::zeros(10, 10, CV_8U)), InputError);
}

TEST(OrbExtractor, ExtractingAgainFromKeptDetectionsGivesExactlyWhatASecondExtractionWould) {
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat img = firstImage();
  ASSERT_FALSE(img.empty());
  feature::OrbExtractor ex(feature::OrbParams{});
  feature::OrbDetections detections;
  const auto first = ex.extract(img, {}, &detections);
  ASSERT_EQ(int(detections.levels.size()), ex.levels());
  // A box in the middle (where a person walks through), and one over most of the image.
  for (const cv::Rect box : {cv::Rect(200, 60, 220, 420), cv::Rect(0, 0, 560, 480)}) {
    cv::Mat skip = cv::Mat::zeros(img.size(), CV_8U);
    skip(box).setTo(255);
    const auto expected = ex.extract(img, skip);
    const auto again = ex.extractAgain(detections, img, skip, first);
    ASSERT_EQ(again.keypoints.size(), expected.keypoints.size());
    ASSERT_GT(expected.keypoints.size(), 500u);
    for (size_t i = 0; i < expected.keypoints.size(); ++i) {
      EXPECT_EQ(again.keypoints[i].pt, expected.keypoints[i].pt);
      EXPECT_EQ(again.keypoints[i].octave, expected.keypoints[i].octave);
      EXPECT_EQ(again.keypoints[i].angle, expected.keypoints[i].angle);
    }
    ASSERT_EQ(again.descriptors.size(), expected.descriptors.size());
    EXPECT_EQ(cv::norm(again.descriptors, expected.descriptors, cv::NORM_HAMMING), 0.0);
  }
  // Detections of another image are refused rather than silently used.
  cv::Mat half;
  cv::resize(img, half, img.size() / 2);
  EXPECT_THROW(ex.extractAgain(detections, half, {}, first), InputError);
  EXPECT_THROW(ex.extractAgain(detections, img, {}, feature::OrbFeatures{first.keypoints, cv::Mat()}), InputError);
}

TEST(OrbExtractor, RejectsBadParametersAndImages) {
  feature::OrbParams p;
  p.scale_factor = 0.9;
  EXPECT_THROW(feature::OrbExtractor{p}, InputError);
  feature::OrbExtractor ex(feature::OrbParams{});
  EXPECT_THROW(ex.extract(cv::Mat(10, 10, CV_8UC3)), InputError);
  EXPECT_EQ(ex.extract(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0))).keypoints.size(), 0u);  // blank image
}

TEST(Quadtree, KeepsTheStrongestPerCellAndHitsTheTarget) {
  std::vector<cv::KeyPoint> kps;
  for (int y = 0; y < 100; y += 2) {
    for (int x = 0; x < 200; x += 2) kps.emplace_back(cv::Point2f(float(x), float(y)), 7.f, -1.f, float((x * 7 + y * 13) % 50));
  }
  const auto out = feature::distributeQuadtree(kps, 0, 200, 0, 100, 64);
  EXPECT_GE(out.size(), 64u);
  EXPECT_LE(out.size(), 64u + 3 * 16);
}

}  // namespace
}  // namespace tkgslam
