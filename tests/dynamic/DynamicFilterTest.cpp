// The multi-view geometry check on synthetic RGB-D views where the truth is known.
#include <tuple>

#include <gtest/gtest.h>

#include "tkgslam/dynamic/DynamicFilter.h"

namespace tkgslam {
namespace {

camera::PinholeCamera makeCamera() {
  camera::CameraParams p;
  p.width = 320;
  p.height = 240;
  p.fx = p.fy = 300;
  p.cx = 160;
  p.cy = 120;
  return camera::PinholeCamera(p);
}

// The object-mask tests' scene: a person-shaped object (kObject) at `object` m in front of a wall
// at `wall` m, in a loose box (looseBox: 40 px of wall left and right of the object).
const cv::Rect kObject(140, 40, 40, 160);
cv::Mat objectBeforeWall(float object, float wall) {
  cv::Mat depth(240, 320, CV_32F, cv::Scalar(wall));
  depth(kObject).setTo(object);
  return depth;
}
dynamic::Detection looseBox() {
  dynamic::Detection d;
  d.box = cv::Rect2f(100, 30, 120, 180);
  return d;
}

// Keypoints on a regular grid with depth read from the given depth image.
std::shared_ptr<data::FrameFeatures> gridFeatures(const cv::Mat& depth, const camera::PinholeCamera& cam) {
  feature::OrbFeatures orb;
  for (int v = 10; v < depth.rows - 10; v += 8) {
    for (int u = 10; u < depth.cols - 10; u += 8) orb.keypoints.emplace_back(cv::Point2f(float(u), float(v)), 31.f);
  }
  orb.descriptors = cv::Mat::zeros(int(orb.keypoints.size()), 32, CV_8U);
  return data::makeFrameFeatures(orb, cv::Mat(), depth, cam, DepthParams{});
}

struct Scene {
  camera::PinholeCamera cam = makeCamera();
  cv::Mat wall = cv::Mat(240, 320, CV_32F, cv::Scalar(3.0f));  // a wall 3 m away
  Pose T_ref = Pose::Identity();
  Pose T_cur = Pose::Identity();
  Scene() { T_cur.translation() = Vec3(-0.1, 0, 0); }  // camera moved 10 cm to the right
};

int countExcluded(const data::FrameFeatures& f, const cv::Rect& r) {
  int n = 0;
  for (int i = 0; i < f.size(); ++i) n += f.excluded[i] && r.contains(cv::Point(f.raw[i].pt));
  return n;
}

TEST(DynamicFilter, RatioIsTheUnionOfTheBoxes) {
  std::vector<dynamic::Detection> boxes(2);
  boxes[0].box = cv::Rect2f(0, 0, 100, 100);
  boxes[1].box = cv::Rect2f(50, 50, 100, 100);  // clipped to 100 x 50, overlaps the first by 50 x 50
  const auto m = dynamic::rasterizeBoxes(boxes, cv::Size(200, 100));
  EXPECT_NEAR(m.ratio, (10000.0 + 5000.0 - 2500.0) / 20000.0, 1e-9);
}

TEST(DynamicFilter, MarginWidensEachBoxByAShareOfItsSize) {
  dynamic::Detection d;
  d.box = cv::Rect2f(50, 20, 40, 20);  // 40 x 20 px
  const auto m = dynamic::rasterizeBoxes({d}, cv::Size(200, 100), 0.1);
  // 4 px more left and right, 2 px more at the top and bottom: 48 x 24.
  EXPECT_EQ(cv::countNonZero(m.mask), 48 * 24);
  EXPECT_EQ(m.mask.at<uchar>(18, 46), 255);
  EXPECT_EQ(m.mask.at<uchar>(17, 46), 0);
  EXPECT_EQ(m.mask.at<uchar>(41, 93), 255);
  EXPECT_EQ(m.mask.at<uchar>(42, 94), 0);
  EXPECT_DOUBLE_EQ(m.ratio, 48.0 * 24.0 / (200.0 * 100.0));
}


// A person-shaped object at 1.5 m in a box over a wall at 3 m: only the object and a band of
// `radius` px around it are masked; the wall seen around the object inside the box is not.
TEST(DynamicFilter, ObjectMaskKeepsTheBackgroundBehindTheObjectInItsBox) {
  cv::Mat depth = objectBeforeWall(1.5f, 3.0f);
  depth(cv::Rect(150, 60, 4, 4)).setTo(0.0f);  // a hole in the object's depth changes nothing
  const dynamic::Detection d = looseBox();
  dynamic::ObjectMaskParams p;
  p.behind = 0.5;
  p.radius = 10;
  const auto m = dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.0, p);
  // The object widened by 10 px, cut to the box at the top and bottom: 60 x 180.
  EXPECT_EQ(cv::countNonZero(m.mask), 60 * 180);
  EXPECT_EQ(m.mask.at<uchar>(100, 130), 255);  // 10 px left of the object
  EXPECT_EQ(m.mask.at<uchar>(100, 129), 0);    // the wall beyond the band
  EXPECT_EQ(m.mask.at<uchar>(100, 105), 0);
  EXPECT_EQ(m.mask.at<uchar>(35, 160), 255);  // above the object, within the band
  EXPECT_DOUBLE_EQ(m.ratio, 60.0 * 180.0 / (320.0 * 240.0));
  // With the whole box as the paper's rule has it, 120 x 180 px would be excluded.
  EXPECT_EQ(cv::countNonZero(dynamic::rasterizeBoxes({d}, depth.size()).mask), 120 * 180);

  // Something nearer than the object (an arm held out, a desk in front) and pixels without
  // depth are masked too: only what is clearly behind the object is left out.
  depth(cv::Rect(105, 100, 10, 10)).setTo(0.8f);
  depth(cv::Rect(200, 150, 10, 10)).setTo(0.0f);
  p.radius = 0;
  const auto near = dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.0, p);
  EXPECT_EQ(cv::countNonZero(near.mask), 40 * 160 + 100 + 100);
  // 1.9 m (0.4 m behind the object) still counts as the object; 2.1 m does not.
  depth(cv::Rect(105, 40, 10, 10)).setTo(1.9f);
  depth(cv::Rect(105, 60, 10, 10)).setTo(2.1f);
  EXPECT_EQ(cv::countNonZero(dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.0, p).mask), 40 * 160 + 300);
}

// The object mask frees the wall in the box, but T stays the boxes' share.
TEST(DynamicFilter, DynamicMaskFreesWhatIsBehindTheObjectButTIsTheBoxesShare) {
  const cv::Mat depth = objectBeforeWall(1.5f, 3.0f);
  const dynamic::Detection d = looseBox();
  dynamic::ObjectMaskParams p;
  p.radius = 0;
  const double box_share = 120.0 * 180.0 / (320.0 * 240.0);
  const auto object = dynamic::dynamicMask({d}, cv::Mat(), depth, 0.0, &p);
  EXPECT_EQ(cv::countNonZero(object.mask), 40 * 160);
  EXPECT_DOUBLE_EQ(object.ratio, box_share);
  const auto boxes = dynamic::dynamicMask({d}, cv::Mat(), depth, 0.0, nullptr);
  EXPECT_EQ(cv::countNonZero(boxes.mask), 120 * 180);
  EXPECT_DOUBLE_EQ(boxes.ratio, box_share);
}

// The depth band behind the object as a share of its size: the same box at half the focal length
// is an object twice as large, with a band twice as deep.
TEST(DynamicFilter, ObjectMaskBandBehindScalesWithTheObjectsSize) {
  cv::Mat depth = objectBeforeWall(1.5f, 3.0f);
  depth(cv::Rect(105, 40, 10, 10)).setTo(1.7f);   // 0.2 m behind the object
  depth(cv::Rect(105, 60, 10, 10)).setTo(1.85f);  // 0.35 m behind
  const dynamic::Detection d = looseBox();
  dynamic::ObjectMaskParams p;
  p.behind = 0.1;  // not used with behind_per_size
  p.radius = 0;
  p.behind_per_size = 0.5;
  p.focal_px = 500;  // 180 px at 1.5 m: 0.54 m, band 0.27 m
  EXPECT_EQ(cv::countNonZero(dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.0, p).mask), 40 * 160 + 100);
  p.focal_px = 250;  // 1.08 m, band 0.54 m
  EXPECT_EQ(cv::countNonZero(dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.0, p).mask), 40 * 160 + 200);
  p.behind_per_size = 0;  // absolute: 0.1 m
  EXPECT_EQ(cv::countNonZero(dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.0, p).mask), 40 * 160);
}

// The same object 0.2 m in front of the wall: depth alone cannot tell the wall in the box from the
// object, colour (GrabCut seeded by depth) can.
TEST(DynamicFilter, ObjectMaskByColourLeavesOutTheNearBackgroundInTheBox) {
  const cv::Mat depth = objectBeforeWall(1.0f, 1.2f);
  // Textured greenish wall, textured reddish object (fixed seeds).
  cv::Mat bgr(depth.size(), CV_8UC3), noise(depth.size(), CV_8UC3);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, cv::Scalar::all(0), cv::Scalar::all(40));
  bgr.setTo(cv::Scalar(60, 150, 70));
  bgr(kObject).setTo(cv::Scalar(50, 40, 170));
  bgr += noise;
  const dynamic::Detection d = looseBox();
  dynamic::ObjectMaskParams p;
  p.behind = 0.5;
  p.radius = 10;
  EXPECT_EQ(cv::countNonZero(dynamic::objectMaskInBoxes({d}, bgr, depth, 0.0, p).mask), 120 * 180);
  p.colour = true;
  const auto m = dynamic::objectMaskInBoxes({d}, bgr, depth, 0.0, p);
  EXPECT_EQ(cv::countNonZero(m.mask(kObject)), kObject.area());  // all of the object
  // The object widened by 10 px is 60 x 180; the quarter-size segmentation adds up to 4 px a side.
  EXPECT_GE(cv::countNonZero(m.mask), 60 * 180);
  EXPECT_LE(cv::countNonZero(m.mask), 68 * 180);
  EXPECT_EQ(m.mask.at<uchar>(100, 105), 0);  // the wall in the box
  // Runs repeat (GrabCut's k-means is seeded).
  EXPECT_EQ(cv::countNonZero(m.mask != dynamic::objectMaskInBoxes({d}, bgr, depth, 0.0, p).mask), 0);
}

// Boxes too small, covering the image or of one flat colour give GrabCut too little to work on:
// the depth mask is used, nothing throws.
TEST(DynamicFilter, ObjectMaskByColourFallsBackToDepthOnDegenerateBoxes) {
  cv::Mat depth(60, 80, CV_32F, cv::Scalar(1.0f));
  const cv::Mat flat(depth.size(), CV_8UC3, cv::Scalar(90, 90, 90));
  dynamic::ObjectMaskParams p;
  p.colour = true;
  p.radius = 0;
  for (const cv::Rect2f box : {cv::Rect2f(30, 20, 6, 6), cv::Rect2f(0, 0, 80, 60), cv::Rect2f(2, 2, 76, 56),
                               cv::Rect2f(20, 10, 40, 40)}) {
    dynamic::Detection d;
    d.box = box;
    const auto colour = dynamic::objectMaskInBoxes({d}, flat, depth, 0.0, p);
    p.colour = false;
    const auto by_depth = dynamic::objectMaskInBoxes({d}, flat, depth, 0.0, p);
    p.colour = true;
    EXPECT_EQ(cv::countNonZero(colour.mask), cv::countNonZero(by_depth.mask)) << box;
  }
}

// The object 0.2 m in front of the wall again, now with a limb sloping away from it: the region a
// depth edge bounds is the object and its limb, the wall in the box is left out - by depth alone.
TEST(DynamicFilter, ObjectMaskByRegionLeavesOutTheBackgroundBeyondADepthEdge) {
  cv::Mat depth = objectBeforeWall(1.0f, 1.2f);
  const cv::Rect limb(180, 150, 30, 40);  // right of the object, 1.0 m at its side to 1.087 m
  for (int u = limb.x; u < limb.br().x; ++u) depth(cv::Rect(u, limb.y, 1, limb.height)).setTo(1.0f + 0.003f * (u - limb.x));
  const dynamic::Detection d = looseBox();
  dynamic::ObjectMaskParams p;
  p.behind = 0.5;
  p.radius = 0;
  EXPECT_EQ(cv::countNonZero(dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.0, p).mask), 120 * 180);
  p.region = true;
  const auto m = dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.0, p);
  EXPECT_EQ(cv::countNonZero(m.mask), kObject.area() + limb.area());
  EXPECT_EQ(m.mask.at<uchar>(160, 209), 255);  // the limb's far end, 1.087 m
  EXPECT_EQ(m.mask.at<uchar>(160, 210), 0);    // the wall next to it (a 10 % step)
  EXPECT_EQ(m.mask.at<uchar>(100, 105), 0);
  // Nearer pixels and pixels without depth in the box stay masked, as in the band.
  depth(cv::Rect(105, 100, 10, 10)).setTo(0.8f);
  depth(cv::Rect(200, 60, 5, 5)).setTo(0.0f);
  EXPECT_EQ(cv::countNonZero(dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.0, p).mask),
            kObject.area() + limb.area() + 100 + 25);
  // Widened by the radius like the band's mask, and cut to the box.
  p.radius = 10;
  const auto wide = dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.0, p);
  EXPECT_EQ(wide.mask.at<uchar>(100, 130), 255);  // 10 px left of the object
  EXPECT_EQ(wide.mask.at<uchar>(100, 129), 0);
  EXPECT_EQ(wide.mask.at<uchar>(100, 124), 255);  // 10 px right of the nearer patch
  EXPECT_EQ(wide.mask.at<uchar>(180, 120), 0);
}

// A box whose central half is mostly wall: the median is the wall's, the region grows over the
// wall, and the object, nearer than the median, is masked all the same - the whole box.
TEST(DynamicFilter, ObjectMaskByRegionKeepsTheObjectWhenTheMedianIsTheBackground) {
  const cv::Mat depth = objectBeforeWall(1.0f, 1.2f);
  dynamic::Detection d;
  d.box = cv::Rect2f(40, 30, 240, 180);  // central half: 120 columns, 40 of them the object's
  dynamic::ObjectMaskParams p;
  p.radius = 0;
  p.region = true;
  const auto m = dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.0, p);
  EXPECT_EQ(cv::countNonZero(m.mask(kObject)), kObject.area());
  EXPECT_EQ(cv::countNonZero(m.mask), 240 * 180);
}

TEST(DynamicFilter, ObjectMaskIsTheWholeBoxWhenItsCentreHasNoDepth) {
  cv::Mat depth(240, 320, CV_32F, cv::Scalar(3.0f));
  dynamic::Detection d;
  d.box = cv::Rect2f(100, 40, 80, 120);
  depth(cv::Rect(120, 70, 40, 60)).setTo(0.0f);  // the box's central half: no depth at all
  const auto m = dynamic::objectMaskInBoxes({d}, cv::Mat(), depth, 0.1, dynamic::ObjectMaskParams{});
  EXPECT_EQ(cv::countNonZero(m.mask), cv::countNonZero(dynamic::rasterizeBoxes({d}, depth.size(), 0.1).mask));
}
TEST(DynamicFilter, BoxOverAStaticWallKeepsItsPoints) {
  Scene s;
  auto ref = gridFeatures(s.wall, s.cam);
  auto cur = gridFeatures(s.wall, s.cam);
  std::vector<dynamic::Detection> boxes(1);
  boxes[0].box = cv::Rect2f(20, 10, 280, 220);  // covers ~80 % of the image
  const auto mask = dynamic::rasterizeBoxes(boxes, s.wall.size());
  ASSERT_GE(mask.ratio, 0.7);
  const int in_box = dynamic::excludeKeypointsInMask(*cur, mask.mask);
  ASSERT_GT(in_box, 500);
  const auto g = dynamic::checkMultiViewGeometry(s.T_cur, s.wall, mask.mask, {{s.T_ref, ref}}, s.cam, {});
  EXPECT_GT(g.projected, 500);
  EXPECT_EQ(g.evidence, 0);
  EXPECT_EQ(dynamic::readmitStaticKeypoints(*cur, mask.mask, g.dynamic_region, s.wall, {}), in_box);
}

// The reference saw the bare wall; now a person stands 1.5 m away in a loose box over most of the
// image, and the current frame's keypoints in it are excluded.
struct PersonBeforeSeenWall : Scene {
  const cv::Rect person{120, 40, 80, 180};
  cv::Mat depth;
  std::shared_ptr<data::FrameFeatures> ref, cur;
  dynamic::BoxMask mask;
  PersonBeforeSeenWall() {
    ref = gridFeatures(wall, cam);
    depth = wall.clone();
    depth(person).setTo(1.5f);
    cur = gridFeatures(depth, cam);
    std::vector<dynamic::Detection> boxes(1);
    boxes[0].box = cv::Rect2f(10, 5, 300, 230);
    mask = dynamic::rasterizeBoxes(boxes, depth.size());
    dynamic::excludeKeypointsInMask(*cur, mask.mask);
  }
  dynamic::GeometryResult check(const dynamic::GeometryParams& p) const {
    return dynamic::checkMultiViewGeometry(T_cur, depth, mask.mask, {{T_ref, ref}}, cam, p);
  }
};

TEST(DynamicFilter, ObjectInFrontOfASeenWallLosesOnlyItsOwnPoints) {
  PersonBeforeSeenWall s;
  const auto& [person, cur, mask] = std::tie(s.person, s.cur, s.mask);
  ASSERT_GE(mask.ratio, 0.7);
  const auto g = s.check({});
  EXPECT_GT(g.evidence, 50);
  dynamic::readmitStaticKeypoints(*cur, mask.mask, g.dynamic_region, s.depth, {});
  // Every keypoint on the person stays excluded; the wall around it is back in use.
  const cv::Rect inner(person.x + 4, person.y + 4, person.width - 8, person.height - 8);
  int on_person = 0;
  for (int i = 0; i < cur->size(); ++i) on_person += inner.contains(cv::Point(cur->raw[i].pt));
  EXPECT_EQ(countExcluded(*cur, inner), on_person);
  int wall_excluded = 0;
  for (int i = 0; i < cur->size(); ++i) {
    const cv::Point p(cur->raw[i].pt);
    const cv::Rect grown(person.x - 6, person.y - 6, person.width + 12, person.height + 12);
    wall_excluded += cur->excluded[i] && !grown.contains(p);
  }
  EXPECT_EQ(wall_excluded, 0);
}

TEST(DynamicFilter, WallKeypointsOnAPersonsOutlineAreNotReadmitted) {
  // As above, with the outline test (dynamic.occluder_radius: 16): wall keypoints whose ORB patch
  // (16 px) reaches the nearer person stay excluded - their corners are its outline and move with it.
  PersonBeforeSeenWall s;
  const auto& [person, cur, mask] = std::tie(s.person, s.cur, s.mask);
  dynamic::GeometryParams params;
  params.occluder_radius = 16;
  const auto g = s.check(params);
  EXPECT_GT(dynamic::readmitStaticKeypoints(*cur, mask.mask, g.dynamic_region, s.depth, params), 300);
  const cv::Rect near_outline(person.x - 16, person.y - 16, person.width + 32, person.height + 32);
  const cv::Rect clear_of_it(person.x - 17, person.y - 17, person.width + 34, person.height + 34);
  int near_wall = 0, near_wall_excluded = 0, far_wall_excluded = 0, in_box = 0;
  for (int i = 0; i < cur->size(); ++i) {
    const cv::Point p(cur->raw[i].pt);
    if (!mask.mask.at<uchar>(p) || person.contains(p)) continue;
    ++in_box;
    if (near_outline.contains(p)) {
      ++near_wall;
      near_wall_excluded += cur->excluded[i];
    } else if (!clear_of_it.contains(p)) {
      far_wall_excluded += cur->excluded[i];
    }
  }
  ASSERT_GT(near_wall, 50);
  EXPECT_EQ(near_wall_excluded, near_wall);
  EXPECT_EQ(far_wall_excluded, 0);
  EXPECT_GT(in_box - near_wall, 300);
}

TEST(DynamicFilter, UnboxedMoverInFrontOfASeenWallIsFound) {
  Scene s;
  auto ref = gridFeatures(s.wall, s.cam);  // the reference saw the bare wall
  cv::Mat depth = s.wall.clone();
  const cv::Rect person(120, 40, 80, 180);
  depth(person).setTo(1.5f);  // a person the detector missed, 1.5 m away
  auto cur = gridFeatures(depth, s.cam);
  const auto g = dynamic::findUnboxedMovers(s.T_cur, depth, cv::Mat(), {{s.T_ref, ref}}, s.cam, {});
  EXPECT_GT(g.evidence, 50);
  EXPECT_GT(dynamic::excludeKeypointsInMask(*cur, g.dynamic_region), 150);
  const cv::Rect inner(person.x + 4, person.y + 4, person.width - 8, person.height - 8);
  int on_person = 0;
  for (int i = 0; i < cur->size(); ++i) on_person += inner.contains(cv::Point(cur->raw[i].pt));
  EXPECT_EQ(countExcluded(*cur, inner), on_person);
  const cv::Rect grown(person.x - 6, person.y - 6, person.width + 12, person.height + 12);
  EXPECT_EQ(countExcluded(*cur, cv::Rect(0, 0, 320, 240)), countExcluded(*cur, grown));  // the wall is kept
}

TEST(DynamicFilter, UnboxedCheckLeavesAStaticObjectSeenByBothViews) {
  // A static box 1.5 m away in front of the wall, in both views. The camera moved 10 cm: the box
  // shifts 20 px, the wall 10 px, so a strip of wall the reference saw is now hidden behind the
  // box (real occlusion by static structure) - but most of what the reference saw of the box
  // itself is found in place, so the box is not a mover.
  Scene s;
  const cv::Rect box_ref(140, 60, 80, 120);
  cv::Mat depth_ref = s.wall.clone(), depth_cur = s.wall.clone();
  depth_ref(box_ref).setTo(1.5f);
  depth_cur(box_ref - cv::Point(20, 0)).setTo(1.5f);  // u_cur = u_ref - fx * 0.1 m / z
  auto ref = gridFeatures(depth_ref, s.cam);
  auto cur = gridFeatures(depth_cur, s.cam);
  const auto g = dynamic::findUnboxedMovers(s.T_cur, depth_cur, cv::Mat(), {{s.T_ref, ref}}, s.cam, {});
  EXPECT_GT(g.evidence, 0);  // the hidden strip
  EXPECT_EQ(cv::countNonZero(g.dynamic_region), 0);
  EXPECT_EQ(dynamic::excludeKeypointsInMask(*cur, g.dynamic_region), 0);
}

TEST(DynamicFilter, UnboxedCheckOnlyLooksOutsideTheBoxes) {
  Scene s;
  auto ref = gridFeatures(s.wall, s.cam);
  cv::Mat depth = s.wall.clone();
  depth(cv::Rect(120, 40, 80, 180)).setTo(1.5f);
  std::vector<dynamic::Detection> boxes(1);
  boxes[0].box = cv::Rect2f(110, 30, 100, 200);  // the detector found this one
  const auto mask = dynamic::rasterizeBoxes(boxes, depth.size());
  const auto g = dynamic::findUnboxedMovers(s.T_cur, depth, mask.mask, {{s.T_ref, ref}}, s.cam, {});
  EXPECT_EQ(g.evidence, 0);
  EXPECT_EQ(cv::countNonZero(g.dynamic_region), 0);
}

TEST(DynamicFilter, ReferenceSelectionPrefersNearbyViews) {
  Pose cur = Pose::Identity();
  std::vector<Pose> cands(4, Pose::Identity());
  cands[0].translation() = Vec3(1.0, 0, 0);
  cands[1].translation() = Vec3(0.05, 0, 0);
  cands[2].linear() = Eigen::AngleAxisd(0.8, Vec3::UnitY()).toRotationMatrix();
  cands[3].translation() = Vec3(0.2, 0, 0);
  const auto sel = dynamic::selectReferenceViews(cur, cands, 3);
  ASSERT_EQ(sel.size(), 3u);
  EXPECT_EQ(sel[0], 1);
  EXPECT_EQ(sel[1], 3);
  EXPECT_EQ(sel[2], 2);  // 0.3 x 1 (rotation) beats 0.7 x 1 (translation)
}

}  // namespace
}  // namespace tkgslam
