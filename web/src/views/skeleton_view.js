// The 3D view: a skeleton drawn from world-space poses with three.js. Bones
// are cylinders from each joint's parent to it, and from a joint to its End
// Site; joints are spheres. Orbit camera (drag, wheel) and a ground grid; the
// camera follows the root across the ground.
import * as THREE from 'three';

import { resizeStage, setUpStage } from './stage.js';

export const BONE_COLOR = 0xff8c1a;
const JOINT_COLOR = 0xf0f0f0;
const UP = new THREE.Vector3(0, 1, 0);

export class SkeletonView {
  constructor(container) {
    setUpStage(this, container);
    this.controls.enableDamping = true;

    this.figure = new THREE.Group();
    this.scene.add(this.figure);
    this.grid = null;
    this.skeleton = null;
    this.bones = [];   // { mesh, from, to } with joint indices, or endSite set
    this.joints = [];  // spheres
    this.framed = false;
    this.lastRoot = null;
    this.followRoot = true;  // off when something else (a mesh) steers the camera
    this.overlay = false;    // thin and see-through, drawn over a mesh
    this.materials = [];

    this.resize();
    this.renderer.setAnimationLoop(() => this.render());
  }

  resize() {
    resizeStage(this);
  }

  render() {
    this.controls.update();
    this.renderer.render(this.scene, this.camera);
  }

  // `skeleton`: the GetSkeleton response (joints with parent and endSite).
  // Bones and joints get their thickness, and the grid its size, from the
  // first pose drawn (sizeFrom).
  setSkeleton(skeleton) {
    for (const child of [...this.figure.children]) {
      this.figure.remove(child);
      child.geometry?.dispose();
    }
    this.skeleton = skeleton;
    this.framed = false;
    this.sized = false;
    this.lastRoot = null;
    const boneGeometry = new THREE.CylinderGeometry(1, 1, 1, 10).translate(0, 0.5, 0);  // spans y ∈ [0, 1]
    const jointGeometry = new THREE.SphereGeometry(1, 12, 8);  // scaled to the joint radius
    const boneMaterial = new THREE.MeshStandardMaterial({ color: BONE_COLOR, roughness: 0.6 });
    const jointMaterial = new THREE.MeshStandardMaterial({ color: JOINT_COLOR, roughness: 0.4 });
    this.materials.forEach((m) => m.dispose());
    this.materials = [boneMaterial, jointMaterial];
    this.bones = [];
    this.joints = skeleton.joints.map((joint, i) => {
      const sphere = new THREE.Mesh(jointGeometry, jointMaterial);
      this.figure.add(sphere);
      const bone = (extra) => {
        const mesh = new THREE.Mesh(boneGeometry, boneMaterial);
        this.figure.add(mesh);
        this.bones.push({ mesh, ...extra });
      };
      if (joint.parent >= 0) bone({ from: joint.parent, to: i });
      if (joint.endSite?.length === 3) bone({ from: i, endSite: new THREE.Vector3(...joint.endSite) });
      return sphere;
    });
    this.setRadius(1e-3);
    this.setOverlay(this.overlay);
  }

  // Sizes bones, joints and (unless a mesh sized it) the grid from world
  // joint positions `positions` (Vector3s): the rest pose's local offsets do
  // not say how big the figure is drawn, as a root scaled by 0.01 above joints
  // in centimetres (Mixamo) shows.
  sizeFrom(positions) {
    const size = figureSize(positions);
    this.setRadius(size * 0.012);
    // Three figures across, as frameOnGrid: the camera (two sizes away) stays
    // off it, so software WebGL draws all of it, not a clipped strip.
    if (this.followRoot) this.setGrid(size / 4);
    this.sized = true;
  }

  setRadius(radius) {
    this.radius = Math.max(radius, 1e-9);
    for (const bone of this.bones) bone.mesh.userData.radius = this.radius;
    this.setOverlay(this.overlay);
  }

  // Overlay: bones half as thick, translucent and drawn over everything (a
  // mesh's surface hides none of them).
  setOverlay(on) {
    this.overlay = on;
    for (const material of this.materials) {
      material.transparent = on;
      material.opacity = on ? 0.6 : 1;
      material.depthTest = !on;
      material.needsUpdate = true;
    }
    const thickness = on ? 0.5 : 1;
    for (const child of this.figure.children) child.renderOrder = on ? 1 : 0;
    for (const joint of this.joints) joint.scale.setScalar(1.7 * (this.radius ?? 1e-3) * thickness);
    for (const bone of this.bones) bone.mesh.userData.thickness = thickness;
  }

  setGrid(size) {
    if (this.grid) this.scene.remove(this.grid);
    const extent = Math.max(size * 12, 1);
    this.grid = new THREE.GridHelper(extent, 48, 0x6a7280, 0x3a4049);
    this.grid.userData.cell = extent / 48;
    this.scene.add(this.grid);
  }

  // A world-space pose of every joint: translations (3 a joint) and
  // rotations (4 a joint, w x y z).
  setPose(pose) {
    if (!this.skeleton) return;
    const n = this.skeleton.joints.length;
    const t = pose.translations;
    const r = pose.rotations;
    if (t.length < 3 * n || r.length < 4 * n) return;
    const position = (i) => new THREE.Vector3(t[3 * i], t[3 * i + 1], t[3 * i + 2]);
    const rotation = (i) => new THREE.Quaternion(r[4 * i + 1], r[4 * i + 2], r[4 * i + 3], r[4 * i]);
    const positions = Array.from({ length: n }, (_, i) => position(i));
    if (!this.sized) this.sizeFrom(positions);
    for (let i = 0; i < n; ++i) this.joints[i].position.copy(positions[i]);
    for (const bone of this.bones) {
      const a = position(bone.from);
      const b = bone.endSite ? bone.endSite.clone().applyQuaternion(rotation(bone.from)).add(a) : position(bone.to);
      placeCylinder(bone.mesh, a, b);
    }
    if (this.followRoot) this.follow(position(0));
  }

  // Frames the figure on its first pose, then keeps the root in view.
  follow(root) {
    if (!this.framed) {
      this.frameBox(new THREE.Box3().setFromObject(this.figure));
      this.framed = true;
    } else if (this.lastRoot) {
      this.panAlongGround(root.clone().sub(this.lastRoot));
    }
    this.lastRoot = root;
  }

  // Moves the camera and its target by `delta`'s shift across the ground; the
  // grid comes along a whole number of cells at a time, so it looks still.
  panAlongGround(delta) {
    delta.setY(0);
    this.controls.target.add(delta);
    this.camera.position.add(delta);
    if (!this.grid) return;
    const cell = this.grid.userData.cell;
    this.grid.position.x = Math.round(this.controls.target.x / cell) * cell;
    this.grid.position.z = Math.round(this.controls.target.z / cell) * cell;
  }

  // Client (page) coordinates of the world point `point` as drawn now.
  screenPosition(point) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const p = point.clone().project(this.camera);
    return { x: rect.left + ((p.x + 1) / 2) * rect.width, y: rect.top + ((1 - p.y) / 2) * rect.height };
  }

  // A raycaster from the camera through the pointer of `event` (clientX, clientY).
  raycaster(event) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(
      ((event.clientX - rect.left) / rect.width) * 2 - 1,
      -((event.clientY - rect.top) / rect.height) * 2 + 1,
    );
    const raycaster = new THREE.Raycaster();
    raycaster.setFromCamera(ndc, this.camera);
    return raycaster;
  }

  // Points the camera at `box` from the front-right, above, and puts the grid
  // under it.
  frameBox(box) {
    const center = box.getCenter(new THREE.Vector3());
    const span = Math.max(...box.getSize(new THREE.Vector3()).toArray(), 1e-3);
    this.controls.target.copy(center);
    this.camera.position.copy(center).add(new THREE.Vector3(1.1, 0.5, 1.6).multiplyScalar(span));
    this.camera.near = span / 100;
    this.camera.far = span * 1000;
    this.camera.updateProjectionMatrix();
    if (!this.grid) this.setGrid(span);
    this.grid.position.y = Math.min(0, box.min.y);
  }
}

function placeCylinder(mesh, a, b) {
  const direction = b.clone().sub(a);
  const length = direction.length();
  mesh.visible = length > 1e-6;
  if (!mesh.visible) return;
  const radius = mesh.userData.radius * (mesh.userData.thickness ?? 1);
  mesh.position.copy(a);
  mesh.scale.set(radius, length, radius);
  mesh.quaternion.setFromUnitVectors(UP, direction.divideScalar(length));
}

// The figure's extent in a pose: the largest side of the joints' bounding
// box (any unit: cm, m, inches; any scale above the joints).
function figureSize(positions) {
  const box = new THREE.Box3().setFromPoints(positions);
  const size = Math.max(...box.getSize(new THREE.Vector3()).toArray());
  return Number.isFinite(size) && size > 0 ? size : 1;
}
