// Forward kinematics and collision bodies of the robot models in data/robots/*.json, mirroring the
// C++ (engine/robots: kinematics.cpp, ur_kinematics.cpp), so the 3D view draws exactly the geometry
// the planner checks. Plain math on 4x4 row-major matrices (arrays of 16); no three.js here.
//
// UR (standard DH): T_(i-1,i) = Rz(q_i) * Tz(d_i) * Tx(a_i) * Rx(alpha_i); frame 0 is the robot's
// base pose in the scene, frame 6 the flange; TCP = frame 6 * tcp_in_flange.
// Gantry: q = [x, y, z]; TCP in frame 0 at (x, y, beam_height - ram_to_tcp - z), tool pointing down
// (a half turn about x); each body is a box whose centre moves with the axes it lists.

export function identity() {
  return [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
}

export function multiply(a, b) {
  const out = new Array(16).fill(0);
  for (let r = 0; r < 4; r++) {
    for (let c = 0; c < 4; c++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[4 * r + k] * b[4 * k + c];
      out[4 * r + c] = s;
    }
  }
  return out;
}

export function translation(x, y, z) {
  return [1, 0, 0, x, 0, 1, 0, y, 0, 0, 1, z, 0, 0, 0, 1];
}

/// Rotation matrix of a unit quaternion [x, y, z, w].
export function quaternionMatrix([x, y, z, w]) {
  return [
    1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), 0,
    2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), 0,
    2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), 0,
    0, 0, 0, 1,
  ];
}

/// {p: [x, y, z], q: [qx, qy, qz, qw]} -> 4x4.
export function poseMatrix(pose) {
  const m = quaternionMatrix(pose.q);
  m[3] = pose.p[0];
  m[7] = pose.p[1];
  m[11] = pose.p[2];
  return m;
}

export function transformPoint(m, [x, y, z]) {
  return [
    m[0] * x + m[1] * y + m[2] * z + m[3],
    m[4] * x + m[5] * y + m[6] * z + m[7],
    m[8] * x + m[9] * y + m[10] * z + m[11],
  ];
}

function dh(q, d, a, alpha) {
  const c = Math.cos(q), s = Math.sin(q), ca = Math.cos(alpha), sa = Math.sin(alpha);
  return [c, -s * ca, s * sa, a * c, s, c * ca, -c * sa, a * s, 0, sa, ca, d, 0, 0, 0, 1];
}

function isGantry(model) {
  return model.kinematics && model.kinematics.beam_height !== undefined;
}

/// Frames 0..6 of a UR arm in the world (frame 0 = base pose).
export function urFrames(model, X_WB, q) {
  const k = model.kinematics;
  const frames = [X_WB];
  for (let i = 0; i < 6; i++) frames.push(multiply(frames[i], dh(q[i], k.d[i], k.a[i], k.alpha[i])));
  return frames;
}

// The gantry's tool frame in its base: a half turn about x (z down).
const GANTRY_TOOL = [1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1];

/// World pose of the TCP.
export function tcpPose(model, X_WB, q) {
  if (isGantry(model)) {
    const k = model.kinematics;
    const m = GANTRY_TOOL.slice();
    m[3] = q[0];
    m[7] = q[1];
    m[11] = k.beam_height - k.ram_to_tcp - q[2];
    return multiply(X_WB, m);
  }
  const frames = urFrames(model, X_WB, q);
  return multiply(frames[6], poseMatrix(model.kinematics.tcp_in_flange));
}

/// Every collision body posed in the world:
///   {name, type: "capsule", a: [x,y,z], b: [x,y,z], radius} or {name, type: "box", pose: 4x4, half: [hx,hy,hz]}.
export function collisionBodies(model, X_WB, q) {
  const out = [];
  if (isGantry(model)) {
    for (const b of model.collision.bodies) {
      const m = b.moves || [];
      const c = b.box.center;
      const centre = [c[0] + (m.includes('x') ? q[0] : 0), c[1] + (m.includes('y') ? q[1] : 0), c[2] - (m.includes('z') ? q[2] : 0)];
      out.push({ name: b.name, type: 'box', pose: multiply(X_WB, translation(...centre)), half: b.box.half_extents });
    }
    return out;
  }
  const frames = urFrames(model, X_WB, q);
  for (const b of model.collision.bodies) {
    const F = frames[b.frame];
    if (b.capsule) {
      out.push({ name: b.name, type: 'capsule', a: transformPoint(F, b.capsule.a), b: transformPoint(F, b.capsule.b), radius: b.capsule.radius });
    } else if (b.box) {
      out.push({ name: b.name, type: 'box', pose: multiply(F, translation(...b.box.center)), half: b.box.half_extents });
    }
  }
  return out;
}
