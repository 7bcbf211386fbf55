// Forward and closed-form inverse kinematics of UR arms (standard DH, see robot_model.h).
//
// IK derivation (frames as in the DH table; n, o, a, p are the columns of the flange pose X_06 in
// the base frame). References: K. P. Hawkins, "Analytic inverse kinematics for the Universal Robots
// UR-5/UR-10 arms" (2013); the same closed form as ur_kinematics/ur_kin.cpp, written here directly
// in standard DH with sines and cosines taken from the geometry instead of acos/asin (better
// conditioned near the branch points, and fewer transcendental calls).
//  - z1 = (s1, -c1, 0). The wrist point p5 = p - d6 a satisfies p5 . z1 = d4, which gives q1
//    (two branches, the shoulder "left/right").
//  - z5 = a and z1 in frame 6 is (c6 s5, -s6 s5, c5), so c5 = a . z1 and |s5| = |a x z1| (two
//    branches: wrist up/down); q6 from n . z1 and o . z1.
//  - y4 = z1, z4 = -(s6 n + c6 o), x4 = c5 (c6 n - s6 o) - s5 a; p4 = p5 - d5 z4. In frame 1 the
//    joints 2, 3, 4 form a planar 3R chain: p4 = (a2 c2 + a3 c23, a2 s2 + a3 s23, d4) and
//    x4 = (c234, s234, 0), which gives q3 (two branches: elbow up/down), q2 and q4.
#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/core/check.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;
// A target this far outside the workspace is still treated as on its boundary (then reached to
// about 1e-11 m): on r^2 - d4^2 (m^2) for the shoulder and on cos q3 for the elbow.
constexpr double kShoulderReachSlack = 1e-12;
constexpr double kElbowCosSlack = 1e-12;

using Mat3 = Eigen::Matrix3d;

// A wrist point that misses the elbow's reach by less than this (on cos q3) may be rounding in q6,
// which is ill-conditioned near a wrist singularity (see WristCircle).
constexpr double kRescueWindow = 1e-6;
// Below this |sin q5| q6 may be off by much more, so any miss is worth the rescue.
constexpr double kNearSingularWrist = 1e-6;
// A solution whose q6 was moved by WristCircle is kept only if it reproduces the target this well.
constexpr double kRescueTolerance = 1e-10;
constexpr int kRescueIterations = 8;

/// Rare path of the IK. The wrist point p4 = p5 + d5 (s6 n + c6 o) runs on a circle as q6 turns; in
/// the arm plane (frame 1 x, z0) its coordinates are (px, py) + d5 (s6 (nx, ny) + c6 (ox, oy)).
/// Near a wrist singularity q6 is ill-conditioned (or set by the reference), and at the edge of the
/// workspace that can leave p4 just out of the elbow's reach.
struct WristCircle {
  double px, py, d5, nx, ny, ox, oy;

  /// Moves q6 to the nearest value (Newton's method on |p4|^2) with |p4|^2 = boundary_r2. If that
  /// stalls, takes the circle's point nearest to (too_far) or farthest from the shoulder instead
  /// (right at a singular wrist; elsewhere the caller's FK check rejects it). False if neither applies.
  bool reachBoundary(double boundary_r2, bool too_far, double& q6) const {
    double t = q6;
    for (int it = 0; it < kRescueIterations; ++it) {
      const double s = std::sin(t), c = std::cos(t);
      const double x = px + d5 * (s * nx + c * ox);
      const double y = py + d5 * (s * ny + c * oy);
      const double f = x * x + y * y - boundary_r2;
      if (std::abs(f) <= 4.0 * std::numeric_limits<double>::epsilon() * boundary_r2) {
        q6 = wrapToPi(t);
        return true;
      }
      const double fp = 2.0 * d5 * (x * (c * nx - s * ox) + y * (c * ny - s * oy));
      if (std::abs(fp) < 1e-12) break;
      t -= std::clamp(f / fp, -0.5, 0.5);
    }
    const double pr = std::sqrt(px * px + py * py);
    if (pr == 0.0) return false;
    const double toward = too_far ? -1.0 : 1.0;
    const double wx = toward * px / pr, wy = toward * py / pr;
    q6 = std::atan2(wx * nx + wy * ny, wx * ox + wy * oy);
    return true;
  }
};

/// R <- R * Rz(q) * Rx(alpha_i) and p <- p + R * (a c, a s, d) for link i (T = Rz Tz Tx Rx).
inline void dhStep(const DhParameters& dh, int i, double c, double s, Mat3& R, Vec3& p) {
  const Vec3 x = c * R.col(0) + s * R.col(1);
  const Vec3 y = c * R.col(1) - s * R.col(0);
  const Vec3 z = R.col(2);
  p += dh.a[i] * x + dh.d[i] * z;
  const double ca = dh.cos_alpha[i];
  const double sa = dh.sin_alpha[i];
  R.col(0) = x;
  R.col(1) = ca * y + sa * z;
  R.col(2) = ca * z - sa * y;
}

inline void setPose(Pose& X, const Mat3& R, const Vec3& p) {
  X.linear() = R;
  X.translation() = p;
  X.makeAffine();
}

/// Moves a wrapped angle into [lo, hi] by +-2 pi if needed; false if it cannot be.
inline bool fitLimit(double& v, double lo, double hi) {
  if (v >= lo && v <= hi) return true;
  if (v + kTwoPi >= lo && v + kTwoPi <= hi) {
    v += kTwoPi;
    return true;
  }
  if (v - kTwoPi >= lo && v - kTwoPi <= hi) {
    v -= kTwoPi;
    return true;
  }
  return false;
}

/// True when FK of q puts the flange at (R, p) in the base frame to kRescueTolerance.
bool reproduces(const RobotModel& model, const double* q, const Mat3& R, const Vec3& p) {
  Mat3 R6 = Mat3::Identity();
  Vec3 p6 = Vec3::Zero();
  for (int i = 0; i < 6; ++i) dhStep(model.dh, i, std::cos(q[i]), std::sin(q[i]), R6, p6);
  return (p6 - p).norm() <= kRescueTolerance && (R6 - R).norm() <= kRescueTolerance;
}

}  // namespace

double wrapToPi(double angle) {
  if (angle > M_PI || angle < -M_PI) {
    angle = std::remainder(angle, kTwoPi);  // exact, result in [-pi, pi]
  }
  return angle;
}

void urFrames(const RobotModel& model, const Pose& X_WB, const JointVector& q,
              std::array<Pose, kUrFrames>& X_W) {
  DASH_DEMAND(model.kinematics == KinematicsKind::kUrDh);
  DASH_DEMAND(q.size() == 6);
  Mat3 R = X_WB.linear();
  Vec3 p = X_WB.translation();
  X_W[0] = X_WB;
  for (int i = 0; i < 6; ++i) {
    double s = 0.0;
    double c = 0.0;
    ::sincos(q[i], &s, &c);
    dhStep(model.dh, i, c, s, R, p);
    setPose(X_W[i + 1], R, p);
  }
}

namespace detail {
FkResult forwardKinematicsUr(const RobotModel& model, const Pose& X_WB, const JointVector& q);

FkResult forwardKinematicsUr(const RobotModel& model, const Pose& X_WB, const JointVector& q) {
  DASH_DEMAND(q.size() == 6);
  Mat3 R = X_WB.linear();
  Vec3 p = X_WB.translation();
  for (int i = 0; i < 6; ++i) {
    double s = 0.0;
    double c = 0.0;
    ::sincos(q[i], &s, &c);
    dhStep(model.dh, i, c, s, R, p);
  }
  FkResult fk;
  setPose(fk.X_WF, R, p);
  const Pose& X_FT = model.dh.X_FT;
  setPose(fk.X_WT, R * X_FT.linear(), p + R * X_FT.translation());
  return fk;
}
}  // namespace detail

namespace {

/// One closed-form IK query (see the derivation at the top), its branches as steps: the shoulder
/// (q1), then the wrist (q5, q6), then the elbow (q2, q3, q4); each solution within the joint limits
/// is written to `out`.
class UrIk {
 public:
  UrIk(const RobotModel& model, const Pose& X_WB, const Pose& X_WT, double q6_reference,
       std::array<JointVector, kUrMaxIkSolutions>& out)
      : model_(model), dh_(model.dh), d1_(dh_.d[0]), a2_(dh_.a[1]), a3_(dh_.a[2]), d4_(dh_.d[3]), d5_(dh_.d[4]),
        d6_(dh_.d[5]), q6_ref_(wrapToPi(q6_reference)), out_(out) {
    // Flange in the base frame: X_B6 = X_WB^-1 X_WT X_FT^-1 (isometries: transpose, no inverse).
    const Mat3 R_WB_T = X_WB.linear().transpose();
    const Mat3 R_BT = R_WB_T * X_WT.linear();
    const Vec3 p_BT = R_WB_T * (X_WT.translation() - X_WB.translation());
    const Mat3 R_FT_T = dh_.X_FT.linear().transpose();
    R_ = R_BT * R_FT_T;
    p_ = p_BT - R_ * dh_.X_FT.translation();
    n_ = R_.col(0);
    o_ = R_.col(1);
    a_ = R_.col(2);
    for (int j = 0; j < 6; ++j) {
      lo_[j] = model.limits.position_min[j];
      hi_[j] = model.limits.position_max[j];
    }
  }

  int solve() {
    // Shoulder pan: p5 . z1 = d4 with z1 = (s1, -c1, 0).
    p5_ = p_ - d6_ * a_;
    const double r2 = p5_.x() * p5_.x() + p5_.y() * p5_.y();
    const double disc = r2 - d4_ * d4_;
    if (disc < -kShoulderReachSlack || r2 == 0.0) return 0;
    const double w_abs = std::sqrt(std::max(disc, 0.0));
    for (int shoulder = 0; shoulder < 2; ++shoulder) {
      if (shoulder == 1 && w_abs == 0.0) break;
      shoulderBranch(shoulder == 0 ? w_abs : -w_abs, r2);
    }
    return count_;
  }

 private:
  void shoulderBranch(double w, double r2) {
    const double c1n = p5_.x() * w - p5_.y() * d4_;
    const double s1n = p5_.y() * w + p5_.x() * d4_;
    q1_ = std::atan2(s1n, c1n);
    c1_ = c1n / r2;
    s1_ = s1n / r2;

    // Wrist 2: c5 = a . z1, |s5| = |a x z1|.
    c5_ = a_.x() * s1_ - a_.y() * c1_;
    const double axy = a_.x() * c1_ + a_.y() * s1_;
    s5_abs_ = std::sqrt(axy * axy + a_.z() * a_.z());
    wrist_singular_ = s5_abs_ < kUrWristSingularTolerance;
    // Wrist 3 for the s5 > 0 branch (the other branch is q6 + pi).
    q6_pos_ = q6_ref_;
    c6_pos_ = 1.0;
    s6_pos_ = 0.0;
    q5_pos_ = c5_ >= 0.0 ? 0.0 : M_PI;
    if (wrist_singular_) {
      c6_pos_ = std::cos(q6_ref_);
      s6_pos_ = std::sin(q6_ref_);
    } else {
      const double u = n_.x() * s1_ - n_.y() * c1_;  //  c6 s5
      const double v = o_.x() * s1_ - o_.y() * c1_;  // -s6 s5
      const double h = std::sqrt(u * u + v * v);
      q6_pos_ = std::atan2(-v, u);
      c6_pos_ = u / h;
      s6_pos_ = -v / h;
      q5_pos_ = std::atan2(s5_abs_, c5_);
    }
    for (int wrist = 0; wrist < 2; ++wrist) {
      if (wrist == 1 && wrist_singular_) break;
      wristBranch(wrist);
    }
  }

  void wristBranch(int wrist) {
    const double sign = wrist == 0 ? 1.0 : -1.0;
    const double s5 = wrist_singular_ ? 0.0 : sign * s5_abs_;
    const double c5e = wrist_singular_ ? (c5_ >= 0.0 ? 1.0 : -1.0) : c5_;
    const double q5 = wrist == 0 ? q5_pos_ : -q5_pos_;
    double c6 = sign * c6_pos_;
    double s6 = sign * s6_pos_;
    double q6 = wrist == 0 ? q6_pos_ : wrapToPi(q6_pos_ + M_PI);

    // Planar 3R chain in frame 1: p4 = (x, y), x4 at angle q234.
    Vec3 p4 = p5_ + d5_ * (s6 * n_ + c6 * o_);  // p5 - d5 z4, z4 = -(s6 n + c6 o)
    double x = p4.x() * c1_ + p4.y() * s1_;
    double y = p4.z() - d1_;
    double c3 = (x * x + y * y - a2_ * a2_ - a3_ * a3_) / (2.0 * a2_ * a3_);
    bool rescued = false;
    if (std::abs(c3) > 1.0 + kElbowCosSlack && (s5_abs_ < kNearSingularWrist || std::abs(c3) < 1.0 + kRescueWindow)) {
      // Edge of the workspace: rounding in an ill-conditioned q6 (nearly singular wrist), or the
      // reference q6 (singular wrist), moved p4 out of reach; move q6 to the nearest value that
      // brings p4 back to the boundary. Verified by FK below.
      const double boundary_r2 = a2_ * a2_ + a3_ * a3_ + 2.0 * a2_ * a3_ * (c3 > 0.0 ? 1.0 : -1.0);
      const WristCircle circle{p5_.x() * c1_ + p5_.y() * s1_, p5_.z() - d1_, d5_,
                               n_.x() * c1_ + n_.y() * s1_, n_.z(), o_.x() * c1_ + o_.y() * s1_, o_.z()};
      const bool too_far = c3 * a2_ * a3_ > 0.0;
      if (circle.reachBoundary(boundary_r2, too_far, q6)) {
        rescued = true;
        s6 = std::sin(q6);
        c6 = std::cos(q6);
        p4 = p5_ + d5_ * (s6 * n_ + c6 * o_);
        x = p4.x() * c1_ + p4.y() * s1_;
        y = p4.z() - d1_;
        c3 = (x * x + y * y - a2_ * a2_ - a3_ * a3_) / (2.0 * a2_ * a3_);
      }
    }
    if (std::abs(c3) > 1.0 + kElbowCosSlack) return;
    const Vec3 x4 = c5e * (c6 * n_ - s6 * o_) - s5 * a_;
    const double q234 = std::atan2(x4.z(), x4.x() * c1_ + x4.y() * s1_);
    elbowBranches(x, y, std::clamp(c3, -1.0, 1.0), q234, q5, q6, rescued);
  }

  void elbowBranches(double x, double y, double c3, double q234, double q5, double q6, bool rescued) {
    const double s3_abs = std::sqrt((1.0 - c3) * (1.0 + c3));
    const double q3_pos = std::atan2(s3_abs, c3);
    const double phi = std::atan2(y, x);
    const double beta_pos = std::atan2(a3_ * s3_abs, a2_ + a3_ * c3);
    for (int elbow = 0; elbow < 2; ++elbow) {
      if (elbow == 1 && s3_abs == 0.0) break;
      const double q3 = elbow == 0 ? q3_pos : -q3_pos;
      const double q2 = wrapToPi(phi - (elbow == 0 ? beta_pos : -beta_pos));
      const double q4 = wrapToPi(q234 - q2 - q3);
      double sol[6] = {q1_, q2, q3, q4, wrapToPi(q5), q6};
      bool ok = true;
      for (int j = 0; j < 6 && ok; ++j) ok = fitLimit(sol[j], lo_[j], hi_[j]);
      if (!ok) continue;
      if (rescued && !reproduces(model_, sol, R_, p_)) continue;
      JointVector& qs = out_[static_cast<std::size_t>(count_++)];
      qs.resize(6);
      for (int j = 0; j < 6; ++j) qs[j] = sol[j];
    }
  }

  const RobotModel& model_;
  const DhParameters& dh_;
  const double d1_, a2_, a3_, d4_, d5_, d6_;
  const double q6_ref_;
  std::array<JointVector, kUrMaxIkSolutions>& out_;
  int count_ = 0;
  Mat3 R_;               ///< flange orientation in the base frame
  Vec3 p_, n_, o_, a_;   ///< flange position; the columns of R_
  Vec3 p5_;              ///< wrist point
  double lo_[6], hi_[6];  ///< joint limits
  // The shoulder branch being solved: q1 and its cosine and sine, the wrist's |s5| and c5.
  double q1_ = 0.0, c1_ = 0.0, s1_ = 0.0, c5_ = 0.0, s5_abs_ = 0.0;
  bool wrist_singular_ = false;
  // The s5 > 0 wrist branch of the shoulder branch.
  double q5_pos_ = 0.0, q6_pos_ = 0.0, c6_pos_ = 0.0, s6_pos_ = 0.0;
};

}  // namespace

int inverseKinematicsUr(const RobotModel& model, const Pose& X_WB, const Pose& X_WT,
                        std::array<JointVector, kUrMaxIkSolutions>& out, double q6_reference) {
  DASH_DEMAND(model.kinematics == KinematicsKind::kUrDh);
  return UrIk(model, X_WB, X_WT, q6_reference, out).solve();
}

}  // namespace dash
