#pragma once
// Forward kinematics of several configurations of one robot at once (issue 38): structure of arrays,
// one lane per configuration, written as plain loops over the lanes that g++ vectorises at -O3 (SSE2
// on any x86-64; AVX2 and AVX-512 clones chosen at run time where the CPU has them). sin and cos come
// from a polynomial kernel (the fdlibm one) that vectorises too. The results agree with
// bodyFrames()/forwardKinematics() to about 1e-15 m (tests/robots/batch_kinematics_test.cpp); they
// feed the conservative covers of engine/collision/link_cover.h, never the exact check.
#include <cstdint>

#include "engine/robots/kinematics.h"

namespace dash {

inline constexpr int kBatchLanes = 8;  ///< configurations per batch
inline constexpr int kBatchMaxJoints = 6;
inline constexpr int kBatchMaxFrames = 12;  ///< UR: the 7 DH frames; gantry: one frame per body

/// Joint values of up to kBatchLanes configurations: q[joint][lane]. Unused lanes must hold finite
/// values (a copy of a used lane does).
struct JointBatch {
  alignas(64) double q[kBatchMaxJoints][kBatchLanes] = {};
  /// Sets lane `lane` to q (q.size() joints).
  void set(int lane, const JointVector& q);
};

/// World poses of a robot's frames for every lane. R[f][3 * column + row][lane] (columns are the
/// frame's axes), p[f][k][lane]; tcp_R, tcp_p: the TCP.
struct FrameBatch {
  int frames = 0;
  alignas(64) double R[kBatchMaxFrames][9][kBatchLanes];
  alignas(64) double p[kBatchMaxFrames][3][kBatchLanes];
  alignas(64) double tcp_R[9][kBatchLanes];
  alignas(64) double tcp_p[3][kBatchLanes];
};

/// Frames of every lane: UR, the DH frames 0..6 (as urFrames); gantry, each body's frame (as
/// bodyFrames). bodyBatchFrame() says which frame a body is rigid in.
void batchFrames(const RobotModel& model, const Pose& X_WB, const JointBatch& q, FrameBatch& out);

/// The frame of FrameBatch that body `body` of `model` is rigid in (bodyFrames()'s frame of that body).
int bodyBatchFrame(const RobotModel& model, int body);

/// The same pose in every lane of (R, p), laid out as in FrameBatch.
void broadcastBatchPose(const Pose& X, double (&R)[9][kBatchLanes], double (&p)[3][kBatchLanes]);

/// sin and cos of kBatchLanes finite angles (|x| < 1e5; tested over +-4 pi), within 4.5e-16 (2 ulp of 1) of libm's.
void sinCosBatch(const double* x, double* s, double* c);

}  // namespace dash
