// The 3D view of a run: its scene (obstacles, support surfaces, objects and their goals) and its
// robots drawn from their collision bodies (capsules and boxes posed by forward kinematics, exactly
// the geometry the planner checks), played back over the plan's time. World frame: z up, metres.
// Drawing is on demand: every change asks for a frame, and the scene is drawn at most once per
// animation frame, only while the view is on screen, and never more than a quarter of the time
// (software WebGL can hold the page most of a second per frame; drawing every update froze the
// Dispatch page so that Abort could not be clicked, issue 41).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';
import { collisionBodies, poseMatrix, tcpPose } from './kinematics.js';
import { PlanPlayer } from './plan_player.js';
import { OKABE_ITO } from './palette.js';

function toThree(m) {
  const out = new THREE.Matrix4();
  out.set(...m);
  return out;
}

const UP = new THREE.Vector3(0, 1, 0);

function segmentLength(a, b) {
  return Math.hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
}

/// three's capsule lies along y and is centred: turn it onto the segment a-b (its length is fixed:
/// a capsule is rigid in its link's frame).
function placeCapsule(mesh, a, b) {
  const va = new THREE.Vector3(...a);
  const vb = new THREE.Vector3(...b);
  const dir = vb.clone().sub(va);
  mesh.position.copy(va).add(vb).multiplyScalar(0.5);
  mesh.quaternion.setFromUnitVectors(UP, dir.length() > 1e-9 ? dir.normalize() : UP);
}

export class PlanViewer {
  /// container: an element; scene, plan (or null), models: as PlanPlayer takes them. live: a view
  /// redrawn continuously (the Dispatch page): no antialiasing and no kept drawing buffer, the two
  /// costliest parts of a frame in software WebGL.
  constructor(container, scene, plan, models, { live = false } = {}) {
    this.container = container;
    this.player = new PlanPlayer(scene, plan, models);
    this.time = 0;
    this.frame = 0; // the pending animation frame, 0 when none
    this.dirty = false;
    this.onScreen = true; // until the IntersectionObserver says otherwise
    this.disposed = false;
    this.frames = 0;
    this.timer = 0; // a frame put off to keep the page free
    this.drawCost = 0; // ms the last frame held the page
    this.drawnAt = 0;
    this.renderer = new THREE.WebGLRenderer({ antialias: !live, preserveDrawingBuffer: !live });
    this.renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
    container.append(this.renderer.domElement);
    this.scene3 = new THREE.Scene();
    this.scene3.background = new THREE.Color(0xeef2f6);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.01, 100);
    this.camera.up.set(0, 0, 1);
    this.scene3.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.4);
    sun.position.set(3, -4, 6);
    this.scene3.add(sun);
    this.buildStatic(scene);
    this.buildRobots();
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.render());
    this.frameCamera(scene);
    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(container);
    this.visibility = new IntersectionObserver((entries) => {
      this.onScreen = entries[entries.length - 1].isIntersecting;
      if (this.onScreen && this.dirty) this.render();
    });
    this.visibility.observe(container);
    this.resize();
    this.setTime(0);
  }

  buildStatic(scene) {
    const bounds = new THREE.Box3();
    const obstacleMaterial = new THREE.MeshStandardMaterial({ color: 0x9aa4ae, roughness: 0.9 });
    for (const o of scene.obstacles) {
      const mesh = new THREE.Mesh(new THREE.BoxGeometry(...o.shape.size), obstacleMaterial);
      mesh.matrixAutoUpdate = false;
      mesh.matrix.copy(toThree(this.poseOf(o.pose)));
      this.scene3.add(mesh);
      bounds.expandByObject(mesh);
    }
    const surfaceMaterial = new THREE.MeshBasicMaterial({ color: 0x56b4e9, transparent: true, opacity: 0.18, side: THREE.DoubleSide });
    for (const s of scene.surfaces) {
      const shape = new THREE.Shape(s.polygon.map(([x, y]) => new THREE.Vector2(x, y)));
      const mesh = new THREE.Mesh(new THREE.ShapeGeometry(shape), surfaceMaterial);
      mesh.position.z = s.z + 0.001;
      this.scene3.add(mesh);
      const edge = new THREE.LineLoop(
        new THREE.BufferGeometry().setFromPoints(s.polygon.map(([x, y]) => new THREE.Vector3(x, y, s.z + 0.002))),
        new THREE.LineBasicMaterial({ color: 0x0072b2 }),
      );
      this.scene3.add(edge);
    }
    this.objectMeshes = {};
    scene.objects.forEach((o, i) => {
      const colour = o.fixed ? 0x7a8591 : new THREE.Color(OKABE_ITO[(i % 6) + 1]);
      const mesh = new THREE.Mesh(new THREE.BoxGeometry(...o.shape.size), new THREE.MeshStandardMaterial({ color: colour, roughness: 0.6 }));
      mesh.matrixAutoUpdate = false;
      this.scene3.add(mesh);
      this.objectMeshes[o.id] = mesh;
      if (o.goal) {
        const ghost = new THREE.LineSegments(
          new THREE.EdgesGeometry(new THREE.BoxGeometry(...o.shape.size)),
          new THREE.LineBasicMaterial({ color: colour }),
        );
        ghost.matrixAutoUpdate = false;
        ghost.matrix.copy(toThree(this.poseOf(o.goal)));
        this.scene3.add(ghost);
      }
    });
    this.bounds = bounds;
  }

  poseOf(pose) {
    return poseMatrix(pose);
  }

  buildRobots() {
    this.robotMeshes = this.player.robots.map((r, i) => {
      const material = new THREE.MeshStandardMaterial({ color: new THREE.Color(OKABE_ITO[i % 2 === 0 ? 0 : 4]), roughness: 0.5, metalness: 0.1 });
      const gripper = new THREE.MeshStandardMaterial({ color: 0x333333, roughness: 0.6 });
      const bodies = collisionBodies(r.model, r.base, r.home);
      return bodies.map((b) => {
        const isGripper = /gripper|finger|tool/.test(b.name);
        const geometry = b.type === 'capsule' ? new THREE.CapsuleGeometry(b.radius, Math.max(segmentLength(b.a, b.b), 1e-6), 4, 12) : new THREE.BoxGeometry(2 * b.half[0], 2 * b.half[1], 2 * b.half[2]);
        const mesh = new THREE.Mesh(geometry, isGripper ? gripper : material);
        if (b.type === 'box') mesh.matrixAutoUpdate = false;
        this.scene3.add(mesh);
        return mesh;
      });
    });
  }

  frameCamera(scene) {
    // The working volume (robots and objects), not the whole table: that is what people look at.
    const box = new THREE.Box3();
    for (const r of scene.robots) {
      const b = new THREE.Vector3(...r.base.p);
      box.expandByPoint(b.clone().add(new THREE.Vector3(-0.5, -0.5, 0)));
      box.expandByPoint(b.clone().add(new THREE.Vector3(0.5, 0.5, 0.9)));
    }
    for (const o of scene.objects) {
      box.expandByPoint(new THREE.Vector3(...o.start.p));
      if (o.goal) box.expandByPoint(new THREE.Vector3(...o.goal.p));
    }
    if (box.isEmpty()) box.copy(this.bounds.isEmpty() ? new THREE.Box3(new THREE.Vector3(-1, -1, 0), new THREE.Vector3(1, 1, 1)) : this.bounds);
    const centre = box.getCenter(new THREE.Vector3());
    const size = Math.max(1, box.getSize(new THREE.Vector3()).length());
    this.camera.position.set(centre.x + 0.6 * size, centre.y - 0.85 * size, centre.z + 0.7 * size);
    this.controls.target.copy(centre);
    this.controls.update();
  }

  resize() {
    const w = this.container.clientWidth || 600;
    const h = this.container.clientHeight || 400;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  /// Poses one robot's meshes (its bodies, or its ghost's) at joints q.
  poseRobot(meshes, r, q) {
    collisionBodies(r.model, r.base, q).forEach((b, k) => {
      const mesh = meshes[k];
      if (b.type === 'capsule') placeCapsule(mesh, b.a, b.b);
      else mesh.matrix.copy(toThree(b.pose));
    });
  }

  /// Poses every robot body and object at time t (seconds into the plan) and redraws.
  setTime(t) {
    this.time = Math.max(0, Math.min(t, this.player.duration));
    this.player.robots.forEach((r, i) => this.poseRobot(this.robotMeshes[i], r, this.player.jointsAt(r, this.time)));
    if (this.ghostMeshes) for (const g of this.ghostMeshes) for (const m of g) m.visible = false;
    this.poseObjects();
  }

  /// Translucent copies of every robot's bodies: where the plan wants the arm while the solid one
  /// shows where it is (the Dispatch page's live view). Made on first use.
  ensureGhosts() {
    if (this.ghostMeshes) return;
    const material = new THREE.MeshBasicMaterial({ color: 0xe69f00, transparent: true, opacity: 0.28, depthWrite: false });
    this.ghostMeshes = this.robotMeshes.map((meshes) =>
      meshes.map((m) => {
        const ghost = new THREE.Mesh(m.geometry, material);
        ghost.matrixAutoUpdate = m.matrixAutoUpdate;
        ghost.visible = false;
        this.scene3.add(ghost);
        return ghost;
      }),
    );
  }

  /// Live view: arms = {robotId: {planned: [q...], actual: [q...]}} draws each listed robot at its
  /// measured joints (solid) with a ghost at its planned joints; other robots and the objects follow
  /// the plan at planTime (seconds into the plan).
  setLive(arms, planTime) {
    this.ensureGhosts();
    this.time = Math.max(0, Math.min(planTime, this.player.duration));
    let worst = 0;
    let live = 0;
    this.player.robots.forEach((r, i) => {
      const a = arms[r.id];
      const planned = a && a.planned && a.planned.length ? a.planned : this.player.jointsAt(r, this.time);
      const actual = a && a.actual && a.actual.length === planned.length ? a.actual : planned;
      this.poseRobot(this.robotMeshes[i], r, actual);
      const ghost = Boolean(a && a.planned && a.planned.length);
      if (ghost) {
        this.poseRobot(this.ghostMeshes[i], r, planned);
        live += 1;
        for (let j = 0; j < planned.length; j++) worst = Math.max(worst, Math.abs(actual[j] - planned[j]));
      }
      for (const m of this.ghostMeshes[i]) m.visible = ghost;
    });
    this.poseObjects();
    Object.assign(this.container.dataset, { live: String(live), liveError: worst.toFixed(4) });
  }

  poseObjects() {
    const objects = this.player.objectsAt(this.time);
    let held = 0;
    for (const [id, state] of Object.entries(objects)) {
      this.objectMeshes[id].matrix.copy(toThree(state.pose));
      if (state.heldBy) held += 1;
    }
    const first = this.player.robots[0];
    const tcp = first ? tcpPose(first.model, first.base, this.player.jointsAt(first, this.time)) : null;
    Object.assign(this.container.dataset, {
      time: this.time.toFixed(3),
      held: String(held),
      tcp0: tcp ? [tcp[3], tcp[7], tcp[11]].map((v) => v.toFixed(3)).join(',') : '',
      bodies: String(this.robotMeshes.reduce((n, m) => n + m.length, 0)),
      objects: String(Object.keys(this.objectMeshes).length),
    });
    this.render();
  }

  /// Asks for the scene to be drawn: once at the next animation frame however often it is asked,
  /// and not while the view is off screen (it is drawn when it comes back).
  render() {
    this.dirty = true;
    if (this.frame || this.timer || this.disposed || !this.onScreen) return;
    // A frame at most every 4 times what the last one held the page: 3/4 of the time stays free for
    // clicks and keys however slow the drawing is.
    const wait = this.drawnAt + 4 * this.drawCost - performance.now();
    if (wait > 1) {
      this.timer = setTimeout(() => {
        this.timer = 0;
        this.render();
      }, wait);
      return;
    }
    this.frame = requestAnimationFrame(() => {
      this.frame = 0;
      if (this.disposed || !this.dirty || !this.onScreen) return;
      this.dirty = false;
      const start = performance.now();
      this.renderer.render(this.scene3, this.camera);
      this.drawnAt = performance.now();
      this.drawCost = this.drawnAt - start;
      this.frames += 1;
      Object.assign(this.container.dataset, { frames: String(this.frames), drawMs: this.drawCost.toFixed(1) });
    });
  }

  dispose() {
    this.disposed = true;
    cancelAnimationFrame(this.frame);
    clearTimeout(this.timer);
    this.visibility.disconnect();
    this.resizeObserver.disconnect();
    this.controls.dispose();
    this.renderer.dispose();
    this.renderer.domElement.remove();
  }
}
