// A dashbench.plan/1 plan played back at any time t (formats.md): joints are linear between points
// and hold after the last one; a grasped object follows its robot's TCP with the grasp's X_TO until
// that robot releases it, then stays where it was put (at its start pose before anything touched it).
import { multiply, poseMatrix, tcpPose } from './kinematics.js';

export class PlanPlayer {
  /// scene: dashbench.scene/1; plan: dashbench.plan/1 or null; models: {name: robot model JSON}.
  constructor(scene, plan, models) {
    this.scene = scene;
    this.plan = plan;
    this.models = models;
    this.robots = scene.robots.map((r) => ({
      id: r.id,
      model: models[r.model],
      base: poseMatrix(r.base),
      home: r.home,
      points: plan && plan.robots[r.id] ? plan.robots[r.id].points : [{ t: 0, q: r.home }],
    }));
    this.byId = Object.fromEntries(this.robots.map((r) => [r.id, r]));
    this.events = plan ? [...plan.events].map((e, i) => ({ ...e, i })).sort((a, b) => a.t - b.t || a.i - b.i) : [];
    this.duration = 0;
    for (const r of this.robots) this.duration = Math.max(this.duration, r.points[r.points.length - 1].t);
    if (plan && typeof plan.makespan === 'number') this.duration = Math.max(this.duration, plan.makespan);
  }

  jointsAt(robot, t) {
    const p = robot.points;
    if (t <= p[0].t) return p[0].q;
    if (t >= p[p.length - 1].t) return p[p.length - 1].q;
    let lo = 0, hi = p.length - 1;
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (p[mid].t <= t) lo = mid;
      else hi = mid;
    }
    const s = (t - p[lo].t) / (p[hi].t - p[lo].t);
    return p[lo].q.map((v, j) => v + s * (p[hi].q[j] - v));
  }

  tcpAt(robot, t) {
    return tcpPose(robot.model, robot.base, this.jointsAt(robot, t));
  }

  /// {objectId: {pose: 4x4, heldBy: robot id or null}} at time t.
  objectsAt(t) {
    const rest = {};
    const holders = {};
    for (const o of this.scene.objects) {
      rest[o.id] = poseMatrix(o.start);
      holders[o.id] = [];
    }
    for (const e of this.events) {
      if (e.t > t) break;
      if (!(e.object in rest) || !this.byId[e.robot]) continue;
      if (e.type === 'grasp') {
        holders[e.object].push({ robot: e.robot, X_TO: poseMatrix(e.X_TO || { p: [0, 0, 0], q: [0, 0, 0, 1] }) });
      } else if (e.type === 'release') {
        const k = holders[e.object].findIndex((h) => h.robot === e.robot);
        if (k >= 0) {
          const h = holders[e.object][k];
          rest[e.object] = multiply(this.tcpAt(this.byId[h.robot], e.t), h.X_TO);
          holders[e.object].splice(k, 1);
        }
      }
    }
    const out = {};
    for (const id of Object.keys(rest)) {
      const h = holders[id][holders[id].length - 1];
      out[id] = h ? { pose: multiply(this.tcpAt(this.byId[h.robot], t), h.X_TO), heldBy: h.robot } : { pose: rest[id], heldBy: null };
    }
    return out;
  }
}
