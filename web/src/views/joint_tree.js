// The joint hierarchy beside the 3D view, as three.js's editor lists a
// scene: every joint's name, indented under its parent. The joint under the
// pointer in the view is highlighted in the list (scrolled to) and ringed in
// the view; pointing at a name rings its joint.
import * as THREE from 'three';

const HIGHLIGHT_COLOR = 0x4fd1ff;

export class JointTree {
  // `root`: the panel (a <ul> inside is filled); `pick(event)`: the joint drawn under the pointer, or -1.
  constructor(root, view, pick) {
    this.root = root;
    this.list = root.querySelector('ul');
    this.view = view;
    this.items = [];
    this.hovered = -1;
    this.marker = new THREE.Mesh(
      new THREE.SphereGeometry(1, 16, 12),
      new THREE.MeshBasicMaterial({ color: HIGHLIGHT_COLOR, transparent: true, opacity: 0.75, depthTest: false }),
    );
    this.marker.renderOrder = 10;  // over bones and meshes
    this.marker.visible = false;
    // Follows its joint while the clip plays.
    this.marker.onBeforeRender = () => this.placeMarker();
    view.scene.add(this.marker);
    const canvas = view.renderer.domElement;
    canvas.addEventListener('pointermove', (e) => this.setHovered(view.figure.visible ? pick(e) : -1));
    canvas.addEventListener('pointerleave', () => this.setHovered(-1));
  }

  // `skeleton`: the GetSkeleton response (joints with names and parents, parents first).
  setSkeleton(skeleton) {
    const depth = [];
    this.items = skeleton.joints.map((joint, i) => {
      depth[i] = joint.parent >= 0 ? depth[joint.parent] + 1 : 0;
      const item = document.createElement('li');
      item.textContent = joint.name;
      item.dataset.joint = String(i);
      item.style.paddingLeft = `${0.3 + depth[i] * 0.8}em`;
      item.addEventListener('pointerenter', () => this.setHovered(i));
      item.addEventListener('pointerleave', () => this.setHovered(-1));
      return item;
    });
    this.list.replaceChildren(...this.items);
    this.hovered = -1;
    this.marker.visible = false;
  }

  setHovered(index) {
    if (index === this.hovered) return;
    this.items[this.hovered]?.classList.remove('hovered');
    this.hovered = index < this.items.length ? index : -1;
    const item = this.items[this.hovered];
    item?.classList.add('hovered');
    item?.scrollIntoView({ block: 'nearest' });
    this.marker.visible = this.hovered >= 0;
    this.placeMarker();
  }

  placeMarker() {
    const sphere = this.view.joints[this.hovered];
    if (!sphere) return;
    this.marker.position.copy(sphere.position);
    this.marker.scale.setScalar(sphere.geometry.parameters.radius * sphere.scale.x * 1.6);
  }
}
