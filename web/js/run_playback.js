// One clock for one or more 3D plan views: a Play button, a speed, a scrubber and the time, shared
// by the run's plan and an overlaid run's plan side by side. Keys (when no text field has focus):
// Space plays or pauses, Left / Right step 1 % of the longest plan, Shift+Left / Right jump to the
// previous / next point of any robot's plan.
import { el } from './dom.js';

const SCRUB_STEPS = 1000;
const KEY_STEP = 0.01;

/// Keys typed into a text field or a list are theirs (the scrubber's arrows are ours).
function typing(target) {
  if (!target) return false;
  if (target.isContentEditable || target.tagName === 'TEXTAREA' || target.tagName === 'SELECT') return true;
  return target.tagName === 'INPUT' && !['range', 'checkbox', 'button'].includes(target.type);
}

export class PlaybackControls {
  /// onSettle(t): the time after a scrub, a key or a pause (not every frame of playback).
  constructor(onSettle = () => {}) {
    this.onSettle = onSettle;
    this.viewers = [];
    this.time = 0;
    this.playing = false;
    this.raf = 0;
    this.scrub = el('input', { type: 'range', min: 0, max: SCRUB_STEPS, value: 0, step: 1, 'data-testid': 'scrubber', 'aria-label': 'plan time' });
    this.play = el('button', { type: 'button', 'data-testid': 'play', title: 'Space' }, 'Play');
    this.speed = el('select', { title: 'playback speed' }, [0.5, 1, 2, 5, 10].map((s) => el('option', { value: s, text: `${s}×`, selected: s === 2 })));
    this.label = el('span', { class: 'mono', 'data-testid': 'time-label', text: 't = 0.00 s' });
    this.element = el('div', { class: 'scrubber' }, this.play, el('label', {}, 'speed', this.speed), this.scrub, this.label);
    this.scrub.addEventListener('input', () => {
      this.showTime((Number(this.scrub.value) / SCRUB_STEPS) * this.duration);
      this.onSettle(this.time);
    });
    this.play.addEventListener('click', () => this.toggle());
    this.onKey = (e) => this.key(e);
    document.addEventListener('keydown', this.onKey);
    this.setViewers([]);
  }

  get duration() {
    return Math.max(0, ...this.viewers.map((v) => v.player.duration));
  }

  /// Viewers that have a plan to play (the controls are disabled without one), shown at time t.
  setViewers(viewers, t = 0) {
    this.viewers = viewers.filter((v) => v && v.player.plan);
    const none = this.viewers.length === 0;
    this.scrub.disabled = none;
    this.play.disabled = none;
    this.pause(false);
    this.showTime(t);
  }

  /// The times at which some robot of some plan has a point (for Shift+arrow).
  planPoints() {
    const times = new Set();
    for (const v of this.viewers) for (const r of v.player.robots) for (const p of r.points) times.add(p.t);
    return [...times].sort((a, b) => a - b);
  }

  showTime(t) {
    const d = this.duration;
    this.time = Math.max(0, Math.min(t, d));
    for (const v of this.viewers) v.setTime(Math.min(this.time, v.player.duration));
    this.label.textContent = `t = ${this.time.toFixed(2)} s / ${d.toFixed(2)} s`;
    this.scrub.value = String(Math.round((SCRUB_STEPS * this.time) / Math.max(1e-9, d)));
  }

  pause(settle = true) {
    const was = this.playing;
    this.playing = false;
    cancelAnimationFrame(this.raf);
    this.play.textContent = 'Play';
    if (was && settle) this.onSettle(this.time);
  }

  toggle() {
    if (this.viewers.length === 0) return;
    if (this.playing) return this.pause();
    this.playing = true;
    this.play.textContent = 'Pause';
    if (this.time >= this.duration) this.showTime(0);
    let last = performance.now();
    const step = (now) => {
      if (!this.playing) return;
      this.showTime(this.time + ((now - last) / 1000) * Number(this.speed.value));
      last = now;
      if (this.time >= this.duration) return this.pause();
      this.raf = requestAnimationFrame(step);
    };
    this.raf = requestAnimationFrame(step);
  }

  key(e) {
    if (this.viewers.length === 0 || typing(e.target) || e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.key === ' ' && e.target && e.target.tagName === 'BUTTON') return; // the button's own click
    if (e.key === ' ') {
      e.preventDefault();
      this.toggle();
    } else if (e.key === 'ArrowRight' || e.key === 'ArrowLeft') {
      e.preventDefault();
      const dir = e.key === 'ArrowRight' ? 1 : -1;
      this.pause();
      if (e.shiftKey) {
        const points = this.planPoints();
        const eps = 1e-9;
        const next = dir > 0 ? points.find((p) => p > this.time + eps) : [...points].reverse().find((p) => p < this.time - eps);
        this.showTime(next ?? (dir > 0 ? this.duration : 0));
      } else {
        this.showTime(this.time + dir * KEY_STEP * this.duration);
      }
      this.onSettle(this.time);
    }
  }

  dispose() {
    this.pause(false);
    document.removeEventListener('keydown', this.onKey);
  }
}
