// Drag a joint and the skeleton follows, by inverse kinematics on the server.
//
// Each drag is one IkSession over a WebSocket (api.openIkSession: the
// TypeScript client's session, in binary frames): the first message sets the effectors and the
// start pose, each drag step sends only the dragged joint's new target and
// gets a pose solved warm from the last one. At most one step is in flight;
// while it runs only the latest target is kept. The session closes when the
// drag ends.
//
// The dragged joint follows the pointer in the plane facing the camera
// through its starting point; the other end joints (hands, feet, head) stay
// pinned where they were, so a hand moves its arm rather than the body.
// Emits 'solve' ({ joint, response }) and 'error' (message) events.
import * as THREE from 'three';
import * as api from '../api.js';
import { LatestWins } from '../latest_wins.js';

const PICK_RADIUS_PX = 16;
const TARGET_COLOR = 0x2ec4ff;

export class IkDrag extends EventTarget {
  // `view`: the SkeletonView drawing the poses; `player`: the clip Player
  // (paused when a drag starts; its poses replace the IK pose).
  constructor(view, player) {
    super();
    this.view = view;
    this.player = player;
    this.enabled = true;  // off while a mesh is shown (its skin would not follow)
    this.local = null;  // the local pose the next solve starts from; null: the clip's at player.time
    this.drag = null;   // { joint, plane, pins, session }
    this.solver = new LatestWins((wanted) => this.solve(wanted));
    // roundTrips: ms per answered drag step (request sent → answer arrived), the latest session's;
    // sessions: the latest few sessions (each one's log: requests, frames, round trips).
    this.stats = { solves: 0, converged: 0, lastResponse: null, sessions: [] };
    this.marker = new THREE.Mesh(
      new THREE.SphereGeometry(1, 16, 12),
      new THREE.MeshBasicMaterial({ color: TARGET_COLOR, transparent: true, opacity: 0.7 }),
    );
    this.marker.visible = false;
    view.scene.add(this.marker);

    const canvas = view.renderer.domElement;
    // Capture phase on the container: a press on a joint never reaches the
    // orbit controls listening on the canvas.
    view.container.addEventListener('pointerdown', (e) => this.onPointerDown(e), { capture: true });
    canvas.addEventListener('pointermove', (e) => this.onPointerMove(e));
    canvas.addEventListener('pointerup', (e) => this.onPointerUp(e));
    canvas.addEventListener('pointercancel', (e) => this.onPointerUp(e));
    // The clip moved on (play, scrub, another clip): start from it next time.
    player.addEventListener('pose', () => {
      if (!this.drag && !this.busy) this.local = null;
    });
  }

  // Client (page) coordinates of joint `index` as drawn now.
  screenPosition(index) {
    return this.view.screenPosition(this.view.joints[index].position);
  }

  // The joint drawn nearest the pointer, within PICK_RADIUS_PX, or -1.
  pick(event) {
    let best = -1;
    let bestDistance = PICK_RADIUS_PX;
    this.view.joints.forEach((_, i) => {
      const s = this.screenPosition(i);
      const d = Math.hypot(s.x - event.clientX, s.y - event.clientY);
      if (d < bestDistance) [best, bestDistance] = [i, d];
    });
    return best;
  }

  // Where the pointer's ray meets the drag plane, or null.
  pointerTarget(event) {
    return this.view.raycaster(event).ray.intersectPlane(this.drag.plane, new THREE.Vector3());
  }

  onPointerDown(event) {
    if (!this.enabled || event.button !== 0 || !this.view.skeleton || !this.player.clip) return;
    if (event.target !== this.view.renderer.domElement) return;  // a panel over the view (the joint list)
    const joint = this.pick(event);
    if (joint < 0) return;
    event.stopPropagation();
    event.preventDefault();
    this.player.pause();
    const joints = this.view.skeleton.joints;
    const position = (i) => this.view.joints[i].position.clone();
    const facing = this.view.camera.getWorldDirection(new THREE.Vector3());
    const hasChild = new Set(joints.map((j) => j.parent));
    const pins = joints
      .map((_, i) => i)
      .filter((i) => i !== joint && !hasChild.has(i))
      .map((i) => ({ joint: joints[i].name, targetPosition: position(i).toArray() }));
    this.drag = {
      joint, plane: new THREE.Plane().setFromNormalAndCoplanarPoint(facing, position(joint)), pins, session: null,
    };
    this.view.renderer.domElement.setPointerCapture?.(event.pointerId);
    this.view.controls.enabled = false;
    this.marker.scale.setScalar(this.view.joints[joint].geometry.parameters.radius * 1.3);
    this.marker.position.copy(position(joint));
    this.marker.visible = true;
  }

  onPointerMove(event) {
    if (!this.drag) return;
    const target = this.pointerTarget(event);
    if (!target) return;
    this.marker.position.copy(target);
    this.solver.request({ drag: this.drag, target });
  }

  // A solve is running or waiting.
  get busy() {
    return this.solver.busy;
  }

  onPointerUp() {
    if (!this.drag) return;
    const { session } = this.drag;
    this.drag = null;
    // The session ends once its last step is answered.
    Promise.resolve(this.solver.running).then(() => session?.then((s) => s.close(), () => {}));
    this.view.controls.enabled = true;
    this.marker.visible = false;
  }

  // The drag's session, opened on its first step with the effectors and the
  // pose to start from; resolves with the session and the start's answer.
  async openSession(drag, target) {
    const clip = this.player.clip;
    if (!this.local) this.local = (await api.evaluate(clip.name, [this.player.time], 'LOCAL')).poses[0];
    const name = this.view.skeleton.joints[drag.joint].name;
    const start = {
      startPose: { rotations: this.local.rotations, translations: this.local.translations },
      effectors: [{ joint: name, targetPosition: target.toArray() }, ...drag.pins],
      options: { regularization: 0.5 },  // prefer small changes from the last pose
      // the hips stay where they stand unless they are what is dragged, then they move
      freeRoot: this.view.skeleton.joints[drag.joint].parent < 0 ? 'ROOT_TRANSLATION' : 'ROOT_FIXED',
    };
    const opened = await api.openIkSession(clip.skeleton, start);
    this.stats.sessions.push(opened.session);
    if (this.stats.sessions.length > 4) this.stats.sessions.shift();
    return opened;
  }

  // One drag step: the first opens the session, later ones move the target.
  async solve({ drag, target }) {
    const name = this.view.skeleton.joints[drag.joint].name;
    try {
      let response;
      if (!drag.session) {
        const opening = this.openSession(drag, target);
        drag.session = opening.then((opened) => opened.session);
        drag.session.catch(() => {});  // reported below, once
        response = (await opening).first;
      } else {
        const session = await drag.session;
        response = await api.ikStep(session, { targets: [{ effector: 0, targetPosition: target.toArray() }] });
      }
      this.local = response.local;
      this.view.setPose(response.world);
      this.stats.solves++;
      if (response.converged) this.stats.converged++;
      this.stats.lastResponse = response;
      this.stats.roundTrips = (await drag.session).log.roundTrips;
      this.dispatchEvent(new CustomEvent('solve', { detail: { joint: name, response } }));
    } catch (error) {
      this.solver.cancel();
      this.dispatchEvent(new CustomEvent('error', { detail: error.message }));
    }
  }
}

