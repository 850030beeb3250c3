// BodyViews: the posed body once per deformation method, side by side on one canvas (a
// viewport each, one camera for all, turned with the mouse), drawn with three.js.
// setRestMesh(mesh): sweepd's Mesh reply (indices, rest positions) becomes one body per method.
// showSet(methods, positions): per method a PosedVertices' positions, 3 per vertex: float16
// (a Uint16Array view into the reply: the GPU gets the half floats as they came) or float32
// (decoded meshopt, vertex_decoding.js). setVisible(methods): which viewports.
// drawIfNeeded(): draws when something changed. viewportRects(): where each viewport is on the
// page, in CSS pixels (for PageStatus and the headless test).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const kMethodColours = { sweep: 0xe07a3f, lbs: 0x3f7ae0, dqs: 0x3fae5a };
const kMethodLabels = { sweep: 'sweep', lbs: 'LBS', dqs: 'DQS' };
const kClearColour = 0x202428;
const kFieldOfViewDegrees = 30;
const kFollowStride = 64;

function halfFloats(values) {
  const halves = new Uint16Array(values.length);
  for (let i = 0; i < values.length; ++i) halves[i] = THREE.DataUtils.toHalfFloat(values[i]);
  return halves;
}

function bodyScene(geometry, colour) {
  // Lambert, flat: the cheapest lit shading, normals from screen-space derivatives (the
  // server sends positions only).
  const body = new THREE.Mesh(geometry,
                              new THREE.MeshLambertMaterial({ color: colour, flatShading: true }));
  body.frustumCulled = false;  // the posed bounds are not recomputed per pose
  const scene = new THREE.Scene();
  const sun = new THREE.DirectionalLight(0xffffff, 2.0);
  sun.position.set(1, 2, 3);
  scene.add(body, sun, new THREE.HemisphereLight(0xffffff, 0x404040, 1.2));
  return { scene, body };
}

export class BodyViews {
  constructor(canvas) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.renderer.setClearColor(kClearColour);
    this.renderer.setScissorTest(true);
    this.camera = new THREE.PerspectiveCamera(kFieldOfViewDegrees, 1, 0.05, 100);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener('change', () => { this.dirty = true; });
    this.views = new Map();  // method -> {scene, body, label}
    this.visible = Object.keys(kMethodColours);
    this.dirty = true;
    new ResizeObserver(() => this.resize()).observe(canvas.parentElement);
  }

  setRestMesh(mesh) {
    const indices = new THREE.BufferAttribute(mesh.indicesArray(), 1);
    const rest = mesh.restPositionsArray();
    const restHalves = halfFloats(rest);
    for (const [method, colour] of Object.entries(kMethodColours)) {
      const geometry = new THREE.BufferGeometry();
      geometry.setIndex(indices);
      geometry.setAttribute('position', new THREE.Float16BufferAttribute(restHalves, 3));
      const label = document.createElement('div');
      label.className = 'view-label';
      label.textContent = kMethodLabels[method];
      this.canvas.parentElement.append(label);
      this.views.set(method, { ...bodyScene(geometry, colour), label });
    }
    this.frame(new THREE.Box3().setFromBufferAttribute(new THREE.BufferAttribute(rest, 3)));
    this.resize();
  }

  // The whole rest body in view, from the front (+z), a little margin above and below.
  frame(bounds) {
    const centre = bounds.getCenter(new THREE.Vector3());
    const height = bounds.max.y - bounds.min.y;
    const distance = (0.6 * height) / Math.tan(THREE.MathUtils.degToRad(kFieldOfViewDegrees / 2));
    this.camera.position.set(centre.x, centre.y, bounds.max.z + distance);
    this.controls.target.copy(centre);
    this.controls.update();
  }

  showSet(methods, positionsPerMethod) {
    methods.forEach((method, i) => {
      const { geometry } = this.views.get(method).body;
      const values = positionsPerMethod[i];
      const attribute = geometry.getAttribute('position');
      if (attribute.array.constructor === values.constructor) {
        attribute.array = values;
        attribute.needsUpdate = true;
      } else {  // the first pose of another format: a new attribute of its type
        geometry.setAttribute('position', values instanceof Float32Array
            ? new THREE.BufferAttribute(values, 3) : new THREE.Float16BufferAttribute(values, 3));
      }
    });
    if (methods.length > 0) this.follow(positionsPerMethod[0]);
    this.dirty = true;
  }

  // Keeps the body in view as a clip moves it about: the camera (and the point it turns about)
  // follows the mean of every kFollowStride-th vertex over the floor (x and z).
  follow(positions) {
    let x = 0;
    let z = 0;
    let count = 0;
    const read = positions instanceof Float32Array ? (v) => v : THREE.DataUtils.fromHalfFloat;
    for (let i = 0; i < positions.length; i += 3 * kFollowStride, ++count) {
      x += read(positions[i]);
      z += read(positions[i + 2]);
    }
    const shift = new THREE.Vector3(x / count - this.controls.target.x, 0,
                                    z / count - this.controls.target.z);
    this.camera.position.add(shift);
    this.controls.target.add(shift);
    this.controls.update();
  }

  setVisible(methods) {
    this.visible = methods;
    this.resize();
  }

  resize() {
    const { clientWidth, clientHeight } = this.canvas.parentElement;
    this.renderer.setSize(clientWidth, clientHeight, false);
    const left = this.canvas.getBoundingClientRect().left;
    this.viewportRects().forEach(({ method, x }) => {
      this.views.get(method).label.style.left = `${x - left + 6}px`;
    });
    for (const [method, view] of this.views) view.label.hidden = !this.visible.includes(method);
    this.dirty = true;
  }

  viewportRects() {
    const box = this.canvas.getBoundingClientRect();
    const width = box.width / Math.max(1, this.visible.length);
    return this.visible.filter((method) => this.views.has(method)).map((method, i) => (
      { method, x: box.left + i * width, y: box.top, width, height: box.height }));
  }

  drawIfNeeded() {
    if (!this.dirty) return false;
    this.dirty = false;
    const box = this.canvas.getBoundingClientRect();
    this.renderer.setScissor(0, 0, box.width, box.height);
    this.renderer.clear();  // all of it: a viewport just hidden leaves nothing behind
    for (const { method, x, width, height } of this.viewportRects()) {
      const left = x - box.left;
      this.renderer.setViewport(left, 0, width, height);
      this.renderer.setScissor(left, 0, width, height);
      this.camera.aspect = width / height;
      this.camera.updateProjectionMatrix();
      this.renderer.render(this.views.get(method).scene, this.camera);
    }
    return true;
  }
}
