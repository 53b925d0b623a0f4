// Drag a vertex and the surface follows, by Laplacian editing on the server.
//
// Pressing on the mesh picks the nearest corner of the triangle under the
// pointer; dragging moves that vertex in the plane facing the camera through
// it. Every vertex dragged so far stays a handle at its last target, so edits
// accumulate. The handles, options and region are one DeformSession over a
// WebSocket (api.openDeformSession: the TypeScript client's session, in binary
// frames), factored once when it opens: each drag step sends the handles'
// targets and gets every vertex back; a new handle, option or radius opens a
// new session. At most one step is in flight, with
// only the latest targets kept.
//
// The region of interest is every vertex within `radius` (a fraction of the
// mesh's diagonal) of a handle, on the same connected piece of the mesh as
// that handle: vertices outside it are held at rest, so the edit stays local
// and the system is well posed (a piece without a handle inside the region
// would float freely, which the server rejects).
// Emits 'deform' ({ response, ms, regionSize }) and 'error' (message).
import * as THREE from 'three';
import * as api from '../api.js';
import { LatestWins } from '../latest_wins.js';

const HANDLE_COLOR = 0x2ec4ff;
const ACTIVE_COLOR = 0xffe14d;

export class VertexDrag extends EventTarget {
  // `view`: the SkeletonView (camera, controls, scene); `meshView`: the
  // MeshView drawing the mesh being edited.
  constructor(view, meshView) {
    super();
    this.view = view;
    this.meshView = meshView;
    this.mesh = null;        // the mesh name while editing, else null
    this.rest = null;        // rest positions (x, y, z per vertex)
    this.component = null;   // connected piece of each vertex
    this.meshSize = 0;
    this.handles = new Map();  // vertex index → target (THREE.Vector3), in drag order
    this.drag = null;          // { index, plane, offset }
    this.options = { method: 'LAPLACIAN', weights: 'UNIFORM', radius: 0.25 };
    this.region = { key: '', vertices: [] };
    this.edits = 0;  // bumped by start and reset: answers for an older edit are dropped
    this.stats = { deforms: 0, sessions: [] };  // sessions: the latest few (each one's log: requests, round trips)
    this.session = null;  // { key, opened: Promise<the client's DeformSession> } for the current handles and options
    this.solver = new LatestWins(() => this.solve());
    this.markers = new THREE.Group();
    view.scene.add(this.markers);

    const canvas = view.renderer.domElement;
    // Capture phase on the container: a press on the mesh never reaches the
    // orbit controls listening on the canvas.
    view.container.addEventListener('pointerdown', (e) => this.onPointerDown(e), { capture: true });
    canvas.addEventListener('pointermove', (e) => this.onPointerMove(e));
    canvas.addEventListener('pointerup', () => this.onPointerUp());
    canvas.addEventListener('pointercancel', () => this.onPointerUp());
  }

  get editing() {
    return this.mesh !== null;
  }

  // Starts editing `meshName`, whose rest shape is `geometry` (a
  // GetMeshGeometry response) and is drawn by the MeshView.
  start(meshName, geometry) {
    this.stop();
    this.mesh = meshName;
    this.region = { key: '', vertices: [] };  // the key names no mesh
    this.rest = Float32Array.from(geometry.positions);
    this.component = connectedPieces(geometry.vertexCount, geometry.triangles ?? []);
    this.meshSize = this.meshView.size() || 1;
  }

  stop() {
    this.reset();
    this.mesh = null;
    this.rest = this.component = null;
  }

  // Drops every handle (the caller shows the rest shape again).
  reset() {
    ++this.edits;
    this.solver.cancel();
    this.closeSession();
    this.onPointerUp();
    this.handles.clear();
    this.updateMarkers();
  }

  // Changes method, weights or radius (a fraction of the mesh's diagonal);
  // the handles are solved again with them.
  setOptions(options) {
    Object.assign(this.options, options);
    if (this.handles.size) this.solver.request();
  }

  get busy() {
    return this.solver.busy;
  }

  // Client (page) coordinates of vertex `index` as drawn now.
  screenPosition(index) {
    return this.view.screenPosition(this.meshView.vertexPosition(index));
  }

  // The corner of the triangle under the pointer nearest the hit, or -1.
  pick(event) {
    const [hit] = this.view.raycaster(event).intersectObject(this.meshView.object, false);
    if (!hit?.face) return -1;
    const corners = [hit.face.a, hit.face.b, hit.face.c];
    const distance = (i) => this.meshView.vertexPosition(i).distanceTo(hit.point);
    return corners.reduce((best, i) => (distance(i) < distance(best) ? i : best));
  }

  onPointerDown(event) {
    if (!this.editing || event.button !== 0 || !this.meshView.object) return;
    const index = this.pick(event);
    if (index < 0) return;  // off the mesh: the orbit controls turn the camera
    event.stopPropagation();
    event.preventDefault();
    const position = this.meshView.vertexPosition(index);
    const facing = this.view.camera.getWorldDirection(new THREE.Vector3());
    const plane = new THREE.Plane().setFromNormalAndCoplanarPoint(facing, position);
    // The vertex keeps its offset from the pointer: it does not jump to it.
    const under = this.view.raycaster(event).ray.intersectPlane(plane, new THREE.Vector3()) ?? position.clone();
    this.drag = { index, plane, offset: position.clone().sub(under) };
    if (!this.handles.has(index)) this.handles.set(index, position);
    this.view.renderer.domElement.setPointerCapture?.(event.pointerId);
    this.view.controls.enabled = false;
    this.updateMarkers();
  }

  onPointerMove(event) {
    if (!this.drag) return;
    const point = this.view.raycaster(event).ray.intersectPlane(this.drag.plane, new THREE.Vector3());
    if (!point) return;
    this.handles.set(this.drag.index, point.add(this.drag.offset));
    this.updateMarkers();
    this.solver.request();
  }

  onPointerUp() {
    if (!this.drag) return;
    this.drag = null;
    this.view.controls.enabled = true;
    this.updateMarkers();
  }

  // One sphere per handle at its target; the one being dragged stands out.
  updateMarkers() {
    const radius = this.meshSize * 0.01;
    while (this.markers.children.length > this.handles.size) {
      const marker = this.markers.children.at(-1);
      this.markers.remove(marker);
      marker.material.dispose();
    }
    while (this.markers.children.length < this.handles.size) {
      const marker = new THREE.Mesh(
        (this.markerGeometry ??= new THREE.SphereGeometry(1, 16, 12)),
        new THREE.MeshBasicMaterial({ transparent: true, opacity: 0.85, depthTest: false }),
      );
      marker.renderOrder = 2;
      this.markers.add(marker);
    }
    [...this.handles].forEach(([index, target], k) => {
      const marker = this.markers.children[k];
      const active = this.drag?.index === index;
      marker.position.copy(target);
      marker.scale.setScalar(active ? radius * 1.4 : radius);
      marker.material.color.set(active ? ACTIVE_COLOR : HANDLE_COLOR);
    });
  }

  // Vertex indices within the radius of a handle, on the handle's piece
  // (rest positions; computed again only when the handles or radius change).
  regionOfInterest() {
    const handles = [...this.handles.keys()];
    const radius = this.options.radius * this.meshSize;
    const key = `${handles.join(',')}|${radius}`;
    if (this.region.key === key) return this.region.vertices;
    const p = this.rest;
    const vertices = [];
    for (let v = 0; v < this.component.length; ++v) {
      const inside = handles.some((h) => this.component[h] === this.component[v] &&
        Math.hypot(p[3 * v] - p[3 * h], p[3 * v + 1] - p[3 * h + 1], p[3 * v + 2] - p[3 * h + 2]) <= radius);
      if (inside) vertices.push(v);
    }
    this.region = { key, vertices };
    return vertices;
  }

  // Ends the current session once the step in flight is answered.
  closeSession() {
    const opened = this.session?.opened;
    this.session = null;
    Promise.resolve(this.solver.running).then(() => opened?.then((s) => s.close(), () => {}));
  }

  // The session for these handles and options, opened (and factored) if new.
  sessionFor(mesh, handles, regionOfInterest) {
    const key = JSON.stringify([mesh, handles, this.options]);  // the region follows from them
    if (this.session?.key === key) return this.session.opened;
    this.closeSession();
    const setup = { mesh, regionOfInterest, method: this.options.method, weights: this.options.weights };
    const opened = api.openDeformSession(setup, handles).then((s) => {  // the setup answered with the rest shape
      this.stats.sessions.push(s);
      if (this.stats.sessions.length > 4) this.stats.sessions.shift();
      return s;
    });
    opened.catch(() => {});  // reported by the step that awaits it
    this.session = { key, opened };
    return opened;
  }

  async solve() {
    const mesh = this.mesh, edit = this.edits;
    if (!mesh || this.handles.size === 0) return;
    const regionOfInterest = this.regionOfInterest();
    const handles = [...this.handles.keys()];
    const positions = [...this.handles.values()].flatMap((target) => target.toArray());
    const started = performance.now();
    try {
      const session = await this.sessionFor(mesh, handles, regionOfInterest);
      // The answers (every vertex) come back as floats, not JSON.
      const response = await api.deformMove(session, positions);
      if (edit !== this.edits) return;  // stopped, reset or restarted meanwhile
      const ms = performance.now() - started;
      this.stats.deforms++;
      this.dispatchEvent(new CustomEvent('deform', { detail: { response, ms, regionSize: regionOfInterest.length } }));
    } catch (error) {
      if (edit === this.edits) this.dispatchEvent(new CustomEvent('error', { detail: error.message }));
    }
  }
}

// The connected piece of each vertex (union-find over the triangles' edges).
function connectedPieces(vertexCount, triangles) {
  const parent = Int32Array.from({ length: vertexCount }, (_, i) => i);
  const root = (v) => {
    while (parent[v] !== v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (let t = 0; t + 2 < triangles.length; t += 3) {
    const a = root(triangles[t]);
    for (const v of [triangles[t + 1], triangles[t + 2]]) parent[root(v)] = a;
  }
  return Int32Array.from({ length: vertexCount }, (_, v) => root(v));
}
