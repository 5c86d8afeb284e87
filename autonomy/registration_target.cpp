#include "autonomy/registration_target.h"

#include <utility>

#include <tbb/task_group.h>

#include "common/error.h"
#include "perception/point_cloud_ops.h"

namespace mopad::autonomy {

struct RegistrationTarget::Impl {
  explicit Impl(const perception::IcpParams& icp) : map(icp) {}
  perception::PointMap map;
  tbb::task_group merge;  // at most one merge in flight
};

RegistrationTarget::RegistrationTarget(const perception::IcpParams& icp)
    : impl_(std::make_unique<Impl>(icp)) {}

RegistrationTarget::~RegistrationTarget() {
  try {
    impl_->merge.wait();
  } catch (...) {  // the owner is gone, and so is whoever would read the error
  }
}

void RegistrationTarget::Add(perception::Points points_S, const Eigen::Isometry3d& X_MS) {
  if (!X_MS.matrix().allFinite())
    throw InputError("", "registered scan pose is not finite", "", "a finite pose");
  Map();  // the previous merge first: merges are applied in the order of the Adds
  impl_->merge.run([this, points = std::move(points_S), X_MS]() {
    impl_->map.Add(perception::Transform(points, X_MS), X_MS.translation());
  });
}

const perception::PointMap& RegistrationTarget::Map() {
  impl_->merge.wait();
  return impl_->map;
}

}  // namespace mopad::autonomy
