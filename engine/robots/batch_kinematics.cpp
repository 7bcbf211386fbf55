// Forward kinematics of kBatchLanes configurations at once (batch_kinematics.h). Every loop runs over
// the lanes with no branch that depends on a lane, so that it vectorises.
#include "engine/robots/batch_kinematics.h"

#include <algorithm>

#include "engine/core/check.h"
#include "engine/core/simd_clones.h"

namespace dash {

namespace {

constexpr int L = kBatchLanes;

/// sin and cos on [-pi/4, pi/4] (fdlibm's __kernel_sin / __kernel_cos polynomials), after a
/// Cody-Waite reduction by k pi/2 (k to nearest, pi/2 in two parts: k pi/2_hi is exact for |k| < 2^20).
inline void sinCosLanes(const double* x, double* s, double* c) {
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  constexpr double kPio2Hi = 1.57079632673412561417e+00;  // first 33 bits of pi/2
  constexpr double kPio2Lo = 6.07710050650619224932e-11;  // pi/2 - kPio2Hi
  constexpr double kRound = 6755399441055744.0;           // 1.5 * 2^52: adding it rounds to an integer
  constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03, S3 = -1.98412698298579493134e-04,
                   S4 = 2.75573137070700676789e-06, S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
  constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03, C3 = 2.48015872894767294178e-05,
                   C4 = -2.75573143513906633035e-07, C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
  for (int l = 0; l < L; ++l) {
    const double k = (x[l] * kTwoOverPi + kRound) - kRound;
    const double r = (x[l] - k * kPio2Hi) - k * kPio2Lo;
    const double z = r * r;
    const double sr = r + r * z * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))));
    const double cr = 1.0 - 0.5 * z + z * z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    const int quadrant = static_cast<int>(k) & 3;
    const double sin_abs = (quadrant & 1) != 0 ? cr : sr;
    const double cos_abs = (quadrant & 1) != 0 ? sr : cr;
    s[l] = (quadrant & 2) != 0 ? -sin_abs : sin_abs;
    c[l] = ((quadrant + 1) & 2) != 0 ? -cos_abs : cos_abs;
  }
}

/// One standard DH step T = Rz(q) Tz(d) Tx(a) Rx(alpha) on every lane (as dhStep in ur_kinematics.cpp).
inline void dhStepLanes(const DhParameters& dh, int i, const double* c, const double* s, double (&R)[9][L],
                        double (&p)[3][L]) {
  const double a = dh.a[static_cast<std::size_t>(i)], d = dh.d[static_cast<std::size_t>(i)];
  const double ca = dh.cos_alpha[static_cast<std::size_t>(i)], sa = dh.sin_alpha[static_cast<std::size_t>(i)];
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < L; ++l) {
      const double x = c[l] * R[k][l] + s[l] * R[3 + k][l];
      const double y = c[l] * R[3 + k][l] - s[l] * R[k][l];
      const double z = R[6 + k][l];
      p[k][l] += a * x + d * z;
      R[k][l] = x;
      R[3 + k][l] = ca * y + sa * z;
      R[6 + k][l] = ca * z - sa * y;
    }
  }
}

/// (R_T, p_T) = (R, p) * X: a fixed pose after a batched one.
inline void composeFixed(const double (&R)[9][L], const double (&p)[3][L], const Pose& X, double (&R_T)[9][L],
                         double (&p_T)[3][L]) {
  double m[3][3], t[3];  // X's rotation and translation, out of Eigen (no aliasing with the lanes)
  for (int i = 0; i < 3; ++i) {
    t[i] = X.translation()[i];
    for (int j = 0; j < 3; ++j) m[i][j] = X.linear()(i, j);
  }
  for (int row = 0; row < 3; ++row) {
    const double* __restrict x = R[row];
    const double* __restrict y = R[3 + row];
    const double* __restrict z = R[6 + row];
    for (int col = 0; col < 3; ++col) {
      double* __restrict out = R_T[3 * col + row];
      for (int l = 0; l < L; ++l) out[l] = x[l] * m[0][col] + y[l] * m[1][col] + z[l] * m[2][col];
    }
    double* __restrict out = p_T[row];
    for (int l = 0; l < L; ++l) out[l] = p[row][l] + (x[l] * t[0] + y[l] * t[1] + z[l] * t[2]);
  }
}

DASH_SIMD_CLONES void urBatch(const DhParameters& dh, const Pose& X_WB, const JointBatch& qb, FrameBatch& out) {
  alignas(64) double R[9][L];
  alignas(64) double p[3][L];
  broadcastBatchPose(X_WB, R, p);
  std::copy(&R[0][0], &R[0][0] + 9 * L, &out.R[0][0][0]);
  std::copy(&p[0][0], &p[0][0] + 3 * L, &out.p[0][0][0]);
  for (int i = 0; i < 6; ++i) {
    alignas(64) double s[L];
    alignas(64) double c[L];
    sinCosLanes(qb.q[i], s, c);
    dhStepLanes(dh, i, c, s, R, p);
    std::copy(&R[0][0], &R[0][0] + 9 * L, &out.R[i + 1][0][0]);
    std::copy(&p[0][0], &p[0][0] + 3 * L, &out.p[i + 1][0][0]);
  }
  composeFixed(R, p, dh.X_FT, out.tcp_R, out.tcp_p);
}

DASH_SIMD_CLONES void gantryBatch(const RobotModel& model, const Pose& X_WB, const JointBatch& qb, FrameBatch& out) {
  const Eigen::Matrix3d& R_WB = X_WB.linear();
  const int bodies = static_cast<int>(model.bodies.size());
  for (int b = 0; b < bodies; ++b) {
    const CollisionBody& body = model.bodies[static_cast<std::size_t>(b)];
    broadcastBatchPose(X_WB, out.R[b], out.p[b]);
    // centre in frame 0: base centre + x, + y, - z for the axes the body follows.
    const double mx = body.moves[0] ? 1.0 : 0.0, my = body.moves[1] ? 1.0 : 0.0, mz = body.moves[2] ? 1.0 : 0.0;
    for (int k = 0; k < 3; ++k) {
      const double base = (R_WB.row(k) * body.gantry_base_center)(0);
      for (int l = 0; l < L; ++l) {
        out.p[b][k][l] +=
            base + R_WB(k, 0) * (mx * qb.q[0][l]) + R_WB(k, 1) * (my * qb.q[1][l]) - R_WB(k, 2) * (mz * qb.q[2][l]);
      }
    }
  }
  // TCP: tool down (a half turn about x), at (x, y, beam_height - ram_to_tcp - z) in frame 0.
  const Eigen::Matrix3d R_WT = R_WB * Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  Pose X_WT = Pose::Identity();
  X_WT.linear() = R_WT;
  broadcastBatchPose(X_WT, out.tcp_R, out.tcp_p);
  const double h = model.gantry.beam_height - model.gantry.ram_to_tcp;
  for (int k = 0; k < 3; ++k) {
    const double origin = X_WB.translation()[k] + R_WB(k, 2) * h;
    for (int l = 0; l < L; ++l)
      out.tcp_p[k][l] = origin + R_WB(k, 0) * qb.q[0][l] + R_WB(k, 1) * qb.q[1][l] - R_WB(k, 2) * qb.q[2][l];
  }
}

}  // namespace

void JointBatch::set(int lane, const JointVector& values) {
  DASH_DEMAND(lane >= 0 && lane < kBatchLanes && values.size() <= kBatchMaxJoints);
  for (Eigen::Index j = 0; j < values.size(); ++j) q[j][lane] = values[j];
}

void sinCosBatch(const double* x, double* s, double* c) { sinCosLanes(x, s, c); }

void broadcastBatchPose(const Pose& X, double (&R)[9][L], double (&p)[3][L]) {
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row) std::fill_n(R[3 * col + row], L, X.linear()(row, col));
  for (int k = 0; k < 3; ++k) std::fill_n(p[k], L, X.translation()[k]);
}

int bodyBatchFrame(const RobotModel& model, int body) {
  return model.kinematics == KinematicsKind::kUrDh ? model.bodies[static_cast<std::size_t>(body)].frame : body;
}

void batchFrames(const RobotModel& model, const Pose& X_WB, const JointBatch& q, FrameBatch& out) {
  if (model.kinematics == KinematicsKind::kUrDh) {
    DASH_DEMAND(model.dof() == 6);
    out.frames = kUrFrames;
    urBatch(model.dh, X_WB, q, out);
    return;
  }
  DASH_DEMAND_MSG(model.bodies.size() <= static_cast<std::size_t>(kBatchMaxFrames), "too many gantry bodies");
  DASH_DEMAND(model.dof() == 3);
  out.frames = static_cast<int>(model.bodies.size());
  gantryBatch(model, X_WB, q, out);
}

}  // namespace dash
