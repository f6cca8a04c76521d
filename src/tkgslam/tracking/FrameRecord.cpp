#include "tkgslam/tracking/FrameRecord.h"

namespace tkgslam::tracking {

Pose FrameRecord::T_cw() const {
  const data::KeyFrame* kf = reference.get();
  Pose T = T_cr;
  while (kf->bad && kf->parent) {
    T = T * kf->T_c_parent;
    kf = kf->parent;
  }
  return T * kf->T_cw();
}

void FrameRecord::setT_cw(const Pose& T) {
  const Pose through_reference = T_cr.inverse() * T_cw();  // T_cw() = T_cr * through_reference
  T_cr = orthonormalized(T * through_reference.inverse());
}

}  // namespace tkgslam::tracking
