// What every 3D view stands on: a renderer in its container, a lit scene on
// the viewer's background, a perspective camera with orbit controls, kept
// sized to the container.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

const BACKGROUND = 0x1c1f24;

// Sets view.container, renderer, scene, camera and controls; calls view.resize() on every size change.
export function setUpStage(view, container, { antialias = true, near = 0.1 } = {}) {
  view.container = container;
  view.renderer = new THREE.WebGLRenderer({ antialias });
  view.renderer.setPixelRatio(window.devicePixelRatio);
  container.appendChild(view.renderer.domElement);

  view.scene = new THREE.Scene();
  view.scene.background = new THREE.Color(BACKGROUND);
  view.scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 2.0));
  const sun = new THREE.DirectionalLight(0xffffff, 1.5);
  sun.position.set(1, 2, 1.5);
  view.scene.add(sun);

  view.camera = new THREE.PerspectiveCamera(45, 1, near, 100000);
  view.controls = new OrbitControls(view.camera, view.renderer.domElement);
  new ResizeObserver(() => view.resize()).observe(container);
}

// The renderer and the camera at the container's size.
export function resizeStage(view) {
  const { clientWidth: w, clientHeight: h } = view.container;
  if (w === 0 || h === 0) return;
  view.renderer.setSize(w, h, false);
  view.camera.aspect = w / h;
  view.camera.updateProjectionMatrix();
}
