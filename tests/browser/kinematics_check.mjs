#!/usr/bin/env node
// The dashboard's forward kinematics (web/js/kinematics.js, which poses the robots in the 3D view)
// against the engine's (`dashbench fk`), for both robot models at several configurations and base
// poses. Exit 0 when every TCP pose agrees within 1e-9 m and 1e-9 in the quaternion.
//   node tests/browser/kinematics_check.mjs --dashbench BUILD/dashbench
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
const i = process.argv.indexOf('--dashbench');
const DASHBENCH = i > 0 ? process.argv[i + 1] : path.join(ROOT, 'build', 'dashbench');
const { poseMatrix, tcpPose, collisionBodies } = await import(path.join(ROOT, 'web', 'js', 'kinematics.js'));

function quaternionOf(m) {
  const [m00, m01, m02, , m10, m11, m12, , m20, m21, m22] = m;
  const tr = m00 + m11 + m22;
  let w, x, y, z;
  if (tr > 0) {
    const s = Math.sqrt(tr + 1) * 2;
    [w, x, y, z] = [0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s];
  } else if (m00 > m11 && m00 > m22) {
    const s = Math.sqrt(1 + m00 - m11 - m22) * 2;
    [w, x, y, z] = [(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s];
  } else if (m11 > m22) {
    const s = Math.sqrt(1 + m11 - m00 - m22) * 2;
    [w, x, y, z] = [(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s];
  } else {
    const s = Math.sqrt(1 + m22 - m00 - m11) * 2;
    [w, x, y, z] = [(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s];
  }
  return w < 0 ? [-x, -y, -z, -w] : [x, y, z, w];
}

const cases = [
  ['ur5e', [0, -1.5708, 1.5708, -1.5708, -1.5708, 0], [0, 0, 0, 0, 0, 0, 1]],
  ['ur5e', [0.3, -1.2, 1.4, -0.5, 0.7, 0.2], [1, 0.5, 0.1, 0, 0, 0.7071067811865476, 0.7071067811865476]],
  ['ur5e', [-2.1, -0.4, 2.2, 1.1, -2.9, 3.0], [1.125, 0, 0, 0, 0, 1, 0]],
  ['gantry3', [0, 0.3, 0], [0, 0, 0, 0, 0, 0, 1]],
  ['gantry3', [0.4, 0.2, 0.1], [0.5, 0, 0.05, 0, 0, 0.3826834323650898, 0.9238795325112867]],
];
let failures = 0;
for (const [robot, q, base] of cases) {
  const out = JSON.parse(execFileSync(DASHBENCH, ['fk', '--robot', robot, '--q', q.join(','), '--base', base.join(',')]).toString());
  const model = JSON.parse(fs.readFileSync(path.join(ROOT, 'data', 'robots', `${robot}.json`)));
  const X_WB = poseMatrix({ p: base.slice(0, 3), q: base.slice(3) });
  const m = tcpPose(model, X_WB, q);
  const p = [m[3], m[7], m[11]];
  let qa = quaternionOf(m);
  let qb = out.tcp.q;
  if (qb[3] < 0) qb = qb.map((v) => -v);
  const dp = Math.max(...p.map((v, k) => Math.abs(v - out.tcp.p[k])));
  const dq = Math.max(...qa.map((v, k) => Math.abs(v - qb[k])));
  const bodies = collisionBodies(model, X_WB, q).length;
  const ok = dp < 1e-9 && dq < 1e-9 && bodies === model.collision.bodies.length;
  if (!ok) failures += 1;
  console.log(`${ok ? 'PASS' : 'FAIL'} ${robot} q=[${q.join(', ')}]: |dp| ${dp.toExponential(1)} m, |dq| ${dq.toExponential(1)}, ${bodies} bodies`);
}
process.exit(failures ? 1 : 0);
