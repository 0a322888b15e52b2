// ccrkit's 3-D view: draws the document that `ccrkit view` embeds as `window.CCRKIT_DATA`.
//
// Units are metres throughout (the document's), the robot's base frame is the scene frame, z up.
// After drawing, `window.ccrkitScene` summarises what was drawn (counts of disks, cables,
// obstacles, contacts per layer) and is mirrored as JSON into `<pre id="ccrkit-scene">` so a
// headless browser's DOM dump can read it back.

import {
  AmbientLight,
  ArrowHelper,
  AxesHelper,
  BufferAttribute,
  BufferGeometry,
  CanvasTexture,
  CatmullRomCurve3,
  Color,
  DirectionalLight,
  DoubleSide,
  ExtrudeGeometry,
  Float32BufferAttribute,
  Group,
  Line,
  LineBasicMaterial,
  Matrix4,
  Mesh,
  MeshStandardMaterial,
  Path,
  PerspectiveCamera,
  Points,
  PointsMaterial,
  Quaternion,
  Scene,
  Shape,
  SphereGeometry,
  BoxGeometry,
  CapsuleGeometry,
  CylinderGeometry,
  Sprite,
  SpriteMaterial,
  TorusGeometry,
  TubeGeometry,
  Vector3,
  WebGLRenderer,
} from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";

const data = window.CCRKIT_DATA;
const summary = { ready: false, layers: [], obstacles: 0, frames: 1, frame: 0, points: 0, port: null };
window.ccrkitScene = summary;

const v3 = (a, i = 0) => new Vector3(a[i], a[i + 1], a[i + 2]);

function publish() {
  const pre = document.getElementById("ccrkit-scene");
  if (pre) pre.textContent = JSON.stringify(summary);
}

// ---------------------------------------------------------------- renderer, camera, controls
const canvasHost = document.getElementById("view");
const renderer = new WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setSize(window.innerWidth, window.innerHeight);
renderer.setClearColor(0xffffff, 1);
canvasHost.appendChild(renderer.domElement);

const scene = new Scene();
scene.add(new AmbientLight(0xffffff, 1.2));
const sun = new DirectionalLight(0xffffff, 1.6);
sun.position.set(1, -1.5, 2);
scene.add(sun);
const camera = new PerspectiveCamera(40, window.innerWidth / window.innerHeight, 1e-4, 100);
camera.up.set(0, 0, 1);
const controls = new OrbitControls(camera, renderer.domElement);
controls.addEventListener("change", render);

function render() {
  renderer.render(scene, camera);
}

window.addEventListener("resize", () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
  render();
});

// ---------------------------------------------------------------- helpers
function textSprite(text, height, color = "#222") {
  const c = document.createElement("canvas");
  const ctx = c.getContext("2d");
  const px = 48;
  ctx.font = `${px}px sans-serif`;
  const w = Math.ceil(ctx.measureText(text).width) + 8;
  c.width = w;
  c.height = px + 12;
  ctx.font = `${px}px sans-serif`;
  ctx.fillStyle = color;
  ctx.textBaseline = "middle";
  ctx.fillText(text, 4, c.height / 2);
  const tex = new CanvasTexture(c);
  const s = new Sprite(new SpriteMaterial({ map: tex, depthTest: false, transparent: true }));
  s.scale.set((height * c.width) / c.height, height, 1);
  s.renderOrder = 10;
  return s;
}

function niceLength(x) {
  const p = Math.pow(10, Math.floor(Math.log10(x)));
  for (const m of [5, 2, 1]) if (m * p <= x) return m * p;
  return p;
}

function fmtLength(m) {
  return m >= 1 ? `${m} m` : m >= 1e-3 ? `${+(m * 1e3).toPrecision(3)} mm` : `${+(m * 1e6).toPrecision(3)} µm`;
}

function lineGeometry(flat) {
  const g = new BufferGeometry();
  g.setAttribute("position", new Float32BufferAttribute(flat, 3));
  return g;
}

// ---------------------------------------------------------------- obstacles
function obstacleMesh(o) {
  let g;
  switch (o.kind) {
    case "sphere":
      g = new SphereGeometry(o.radius, 32, 16);
      break;
    case "box":
      g = new BoxGeometry(2 * o.half_extents[0], 2 * o.half_extents[1], 2 * o.half_extents[2]);
      break;
    case "capsule":
      g = new CapsuleGeometry(o.radius, 2 * o.half_height, 8, 24);
      g.rotateX(Math.PI / 2); // three's capsules run along y; ccrkit's along local z
      break;
    case "cylinder":
      g = new CylinderGeometry(o.radius, o.radius, 2 * o.half_height, 32);
      g.rotateX(Math.PI / 2);
      break;
    case "mesh":
      g = new BufferGeometry();
      g.setAttribute("position", new Float32BufferAttribute(o.vertices, 3));
      g.setIndex(new BufferAttribute(new Uint32Array(o.triangles), 1));
      g.computeVertexNormals();
      break;
    default:
      throw new Error(`unknown obstacle kind ${o.kind}`);
  }
  const m = new Mesh(
    g,
    new MeshStandardMaterial({
      color: 0x8a9bb0,
      transparent: true,
      opacity: 0.16,
      side: DoubleSide,
      depthWrite: false,
    }),
  );
  m.position.copy(v3(o.position));
  m.quaternion.copy(new Quaternion(o.quaternion[0], o.quaternion[1], o.quaternion[2], o.quaternion[3]));
  m.name = `obstacle:${o.name}`;
  return m;
}

// ---------------------------------------------------------------- a robot layer
const robot = data.robot;

function diskGeometry(k) {
  const outline = new Shape();
  outline.absarc(0, 0, robot.disk_radius, 0, 2 * Math.PI, false);
  for (const h of robot.holes[k] || []) {
    const p = new Path();
    p.absarc(h[0], h[1], robot.hole_radius, 0, 2 * Math.PI, true);
    outline.holes.push(p);
  }
  const g = new ExtrudeGeometry(outline, { depth: robot.disk_thickness, bevelEnabled: false, curveSegments: 24 });
  g.translate(0, 0, -robot.disk_thickness / 2);
  return g;
}

class Layer {
  constructor(spec, index, diskGeoms, arrowScale) {
    this.spec = spec;
    this.color = new Color(spec.color);
    this.group = new Group();
    this.group.name = `layer:${spec.label}`;
    scene.add(this.group);
    this.arrowScale = arrowScale;
    this.diskMat = new MeshStandardMaterial({
      color: this.color,
      transparent: true,
      opacity: index === 0 ? 0.55 : 0.35,
      depthWrite: false,
    });
    this.disks = diskGeoms.map((g) => {
      const m = new Mesh(g, this.diskMat);
      this.group.add(m);
      return m;
    });
    this.tubeMat = new MeshStandardMaterial({ color: this.color, roughness: 0.5 });
    this.tube = null;
    const cableColor = this.color.clone().lerp(new Color(0x000000), 0.35);
    this.cables = spec.frames[0].cables.map((c) => {
      const l = new Line(lineGeometry(c.points), new LineBasicMaterial({ color: cableColor }));
      this.group.add(l);
      return l;
    });
    this.contacts = new Group();
    this.group.add(this.contacts);
    this.counts = { label: spec.label, method: spec.method, disks: 0, cables: 0, contacts: 0, backbone_points: 0 };
  }

  show(f) {
    const fr = this.spec.frames[Math.min(f, this.spec.frames.length - 1)];
    const m = new Matrix4();
    fr.disks.forEach((d, k) => {
      // d = [px, py, pz, r00, r01, r02, r10, ..., r22] with r row-major.
      m.set(d[3], d[4], d[5], d[0], d[6], d[7], d[8], d[1], d[9], d[10], d[11], d[2], 0, 0, 0, 1);
      if (this.disks[k]) {
        this.disks[k].matrixAutoUpdate = false;
        this.disks[k].matrix.copy(m);
      }
    });
    if (this.tube) {
      this.group.remove(this.tube);
      this.tube.geometry.dispose();
    }
    const pts = [];
    for (let i = 0; i + 2 < fr.backbone.length; i += 3) pts.push(v3(fr.backbone, i));
    const curve = new CatmullRomCurve3(pts, false, "centripetal");
    this.tube = new Mesh(
      new TubeGeometry(curve, Math.max(64, pts.length * 2), robot.backbone_radius, 12, false),
      this.tubeMat,
    );
    this.group.add(this.tube);
    fr.cables.forEach((c, i) => {
      const l = this.cables[i];
      if (!l) return;
      l.geometry.dispose();
      l.geometry = lineGeometry(c.points);
    });
    for (const a of [...this.contacts.children]) {
      this.contacts.remove(a);
      a.dispose();
    }
    for (const c of fr.contacts) {
      const len = Math.max(Math.abs(c.reaction) * this.arrowScale, robot.disk_radius * 0.25);
      const dir = v3(c.normal).normalize();
      const a = new ArrowHelper(dir, v3(c.point), len, 0xd62728, len * 0.25, len * 0.12);
      a.name = `contact:${c.obstacle}:${c.feature}`;
      this.contacts.add(a);
    }
    this.counts.disks = fr.disks.length;
    this.counts.cables = fr.cables.length;
    this.counts.contacts = this.contacts.children.length;
    this.counts.backbone_points = pts.length;
  }
}

// ---------------------------------------------------------------- build the scene
const obstacles = new Group();
for (const o of data.obstacles) obstacles.add(obstacleMesh(o));
scene.add(obstacles);
summary.obstacles = obstacles.children.length;

// One arrow scale per contact unit (N for energy, rad/m for the geometric methods: never
// mixed): the largest reaction of that unit spans a quarter of the robot's length.
const robotLength = robot.length;
const maxReaction = {};
for (const l of data.layers)
  for (const f of l.frames)
    for (const c of f.contacts)
      maxReaction[l.contact_unit] = Math.max(maxReaction[l.contact_unit] || 0, Math.abs(c.reaction));
const arrowScaleOf = (unit) => (maxReaction[unit] > 0 ? (0.25 * robotLength) / maxReaction[unit] : 0);

const diskGeoms = robot.holes.map((_, k) => diskGeometry(k));
const layers = data.layers.map((spec, i) => new Layer(spec, i, diskGeoms, arrowScaleOf(spec.contact_unit)));
summary.frames = Math.max(1, ...data.layers.map((l) => l.frames.length));

// The entry port: a ring at the port frame and the channel behind it, along its −z (the robot
// comes out along +z; each frame's shape already holds the insertion and rotation, the
// label names them).
if (robot.port) {
  const ringR = 1.6 * Math.max(robot.disk_radius, robot.backbone_radius);
  const port = new Group();
  port.name = "port";
  port.add(new Mesh(new TorusGeometry(ringR, 0.12 * ringR, 12, 48), new MeshStandardMaterial({ color: 0x444444 })));
  const channel = new Mesh(
    new CylinderGeometry(0.9 * ringR, 0.9 * ringR, robot.length, 24, 1, true),
    new MeshStandardMaterial({ color: 0x888888, transparent: true, opacity: 0.15, depthWrite: false, side: DoubleSide }),
  );
  channel.rotateX(Math.PI / 2); // three's cylinders run along y; the channel along the port's z
  channel.position.z = -robot.length / 2;
  port.add(channel);
  port.position.set(...robot.port.position);
  port.quaternion.set(...robot.port.quaternion);
  scene.add(port);
}

function showFrame(f) {
  summary.frame = f;
  for (const l of layers) l.show(f);
  summary.layers = layers.map((l) => l.counts);
  // Insertion and rotation at this waypoint (the first layer solved through the port).
  const st = layers.map((l) => l.spec.frames[Math.min(f, l.spec.frames.length - 1)].port).find((p) => p);
  summary.port = st ? { insertion: st[0], rotation: st[1] } : null;
  const label = document.getElementById("frame-label");
  const port = st ? ` · inserted ${(1000 * st[0]).toFixed(1)} mm · turned ${st[1].toFixed(3)} rad` : "";
  if (label) label.textContent = `waypoint ${f + 1} / ${summary.frames}${port}`;
  publish();
  render();
}

// Base frame, ground grid and scale bar.
const axesLen = robot.disk_radius * 2;
scene.add(new AxesHelper(axesLen));
for (const [t, p] of [["x", [1, 0, 0]], ["y", [0, 1, 0]], ["z", [0, 0, 1]]]) {
  const s = textSprite(t, axesLen * 0.35);
  s.position.set(p[0] * axesLen * 1.15, p[1] * axesLen * 1.15, p[2] * axesLen * 1.15);
  scene.add(s);
}

// Bounds of everything drawn (robot frames, cloud, obstacles near the robot).
const lo = new Vector3(Infinity, Infinity, Infinity);
const hi = new Vector3(-Infinity, -Infinity, -Infinity);
const grow = (p) => {
  lo.min(p);
  hi.max(p);
};
grow(new Vector3(0, 0, 0));
for (const l of data.layers)
  for (const f of l.frames) for (let i = 0; i + 2 < f.backbone.length; i += 3) grow(v3(f.backbone, i));
if (data.cloud) for (let i = 0; i + 2 < data.cloud.points.length; i += 3) grow(v3(data.cloud.points, i));
grow(new Vector3(robot.disk_radius, robot.disk_radius, robotLength));
grow(new Vector3(-robot.disk_radius, -robot.disk_radius, 0));
const size = hi.clone().sub(lo);
const extent = Math.max(size.x, size.y, size.z);

const bar = niceLength(extent * 0.3);
{
  const y0 = lo.y - extent * 0.08;
  const x0 = lo.x;
  const g = lineGeometry([x0, y0, 0, x0 + bar, y0, 0, x0, y0, 0, x0, y0, extent * 0.02, x0 + bar, y0, 0, x0 + bar, y0, extent * 0.02]);
  const segs = new Line(g, new LineBasicMaterial({ color: 0x222222 }));
  segs.name = "scale-bar";
  scene.add(segs);
  const s = textSprite(fmtLength(bar), extent * 0.04);
  s.position.set(x0 + bar / 2, y0, extent * 0.045);
  scene.add(s);
  summary.scale_bar_m = bar;
}

// Sweep: the tip cloud coloured by a column.
let cloud = null;
function colorCloud(column) {
  const spec = data.cloud.columns.find((c) => c.name === column);
  const vals = spec.values;
  // A loop, not Math.min(...vals): a sweep can have more values than a call takes arguments.
  let vmin = Infinity;
  let vmax = -Infinity;
  for (const x of vals) {
    if (Number.isFinite(x)) {
      vmin = Math.min(vmin, x);
      vmax = Math.max(vmax, x);
    }
  }
  const col = new Float32Array(vals.length * 3);
  const c = new Color();
  vals.forEach((x, i) => {
    if (!Number.isFinite(x)) c.setRGB(0.6, 0.6, 0.6);
    else {
      const t = vmax > vmin ? (x - vmin) / (vmax - vmin) : 0.5;
      c.setHSL(0.66 * (1 - t), 0.85, 0.45); // blue (low) → red (high)
    }
    col.set([c.r, c.g, c.b], 3 * i);
  });
  cloud.geometry.setAttribute("color", new BufferAttribute(col, 3));
  summary.color_by = column;
  const cb = document.getElementById("colorbar-range");
  const cats = spec.categories || [];
  if (cb)
    cb.textContent = cats.length
      ? cats.map((n, k) => `${k}: ${n}`).join(", ")
      : `${vmin.toPrecision(4)} … ${vmax.toPrecision(4)}`;
  publish();
  render();
}
if (data.cloud) {
  const g = new BufferGeometry();
  g.setAttribute("position", new Float32BufferAttribute(data.cloud.points, 3));
  cloud = new Points(g, new PointsMaterial({ size: extent * 0.012, vertexColors: true }));
  cloud.name = "tip-cloud";
  scene.add(cloud);
  summary.points = data.cloud.points.length / 3;
}

// ---------------------------------------------------------------- legend and controls (HTML)
function el(tag, attrs = {}, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

function legend() {
  const box = document.getElementById("legend");
  box.appendChild(el("div", { class: "title" }, data.title));
  for (const l of data.layers) {
    const row = el("div", { class: "row" });
    const sw = el("span", { class: "swatch" });
    sw.style.background = l.color;
    row.appendChild(sw);
    row.appendChild(document.createTextNode(l.label));
    box.appendChild(row);
  }
  const f0 = data.layers.length ? data.layers[0].frames[0] : null;
  if (f0 && f0.cables.length) {
    const names = f0.cables.map((c) => c.name + (c.slack ? " (slack)" : "")).join(", ");
    box.appendChild(el("div", { class: "row" }, `— cables: ${names}`));
  }
  box.appendChild(el("div", { class: "row" }, `${robot.holes.length} disks (0 = base), holes Ø ${fmtLength(2 * robot.hole_radius)}`));
  if (data.obstacles.length) {
    const row = el("div", { class: "row" });
    const sw = el("span", { class: "swatch" });
    sw.style.background = "rgba(138,155,176,0.5)";
    row.appendChild(sw);
    row.appendChild(document.createTextNode(`obstacles: ${data.obstacles.map((o) => o.name).join(", ")}`));
    box.appendChild(row);
  }
  for (const [unit, max] of Object.entries(maxReaction)) {
    if (!(max > 0)) continue;
    const row = el("div", { class: "row" });
    const sw = el("span", { class: "swatch" });
    sw.style.background = "#d62728";
    row.appendChild(sw);
    const who = data.layers.filter((l) => l.contact_unit === unit).map((l) => l.label.split(" ")[0]);
    row.appendChild(
      document.createTextNode(
        `contact reactions (${who.join(", ")}): ${fmtLength(bar)} arrow = ${(bar / arrowScaleOf(unit)).toPrecision(3)} ${unit || "(no unit)"}`,
      ),
    );
    box.appendChild(row);
  }
  box.appendChild(el("div", { class: "row small" }, `base frame: x red, y green, z blue; scale bar ${fmtLength(bar)}`));
  box.appendChild(el("div", { class: "row small" }, "drag: orbit · wheel: zoom · right-drag: pan"));
}

function planControls() {
  const box = document.getElementById("controls");
  box.hidden = false;
  const slider = el("input", { type: "range", min: "0", max: String(summary.frames - 1), value: "0", id: "frame" });
  const play = el("button", { id: "play" }, "▶");
  box.appendChild(play);
  box.appendChild(slider);
  box.appendChild(el("span", { id: "frame-label" }));
  slider.addEventListener("input", () => showFrame(Number(slider.value)));
  let timer = null;
  play.addEventListener("click", () => {
    if (timer) {
      clearInterval(timer);
      timer = null;
      play.textContent = "▶";
      return;
    }
    play.textContent = "❚❚";
    // Whole plan in about 10 s, at most 60 frames per second.
    const dt = Math.max(1000 / 60, 10000 / summary.frames);
    timer = setInterval(() => {
      const f = (Number(slider.value) + 1) % summary.frames;
      slider.value = String(f);
      showFrame(f);
    }, dt);
  });
}

function cloudControls() {
  const box = document.getElementById("controls");
  box.hidden = false;
  box.appendChild(el("span", {}, "colour by "));
  const sel = el("select", { id: "color-by" });
  for (const c of data.cloud.columns) sel.appendChild(el("option", { value: c.name }, c.name));
  sel.value = data.cloud.color_by;
  sel.addEventListener("change", () => colorCloud(sel.value));
  box.appendChild(sel);
  box.appendChild(el("span", { class: "colorbar" }));
  box.appendChild(el("span", { id: "colorbar-range" }));
}

// ---------------------------------------------------------------- go
legend();
if (summary.frames > 1) planControls();
if (data.cloud) {
  cloudControls();
  colorCloud(data.cloud.color_by);
}
const centre = lo.clone().add(hi).multiplyScalar(0.5);
controls.target.copy(centre);
camera.position.copy(centre.clone().add(new Vector3(0.45, -1.9, 0.55).multiplyScalar(extent * 1.05)));
camera.near = extent * 1e-3;
camera.far = extent * 100;
camera.updateProjectionMatrix();
controls.update();
// `#frame=K`: open at waypoint K (0-based), e.g. to read its insertion and rotation back.
const start = /^#frame=(\d+)$/.exec(location.hash);
showFrame(start ? Math.min(Number(start[1]), summary.frames - 1) : 0);
// `#step-all`: show 100 frames spread over the path and record what a frame change costs:
// the scene update alone (the script's part, what a slider drag waits for besides the GPU)
// and with the draw finished, so a test can tell a long plan stays interactive.
if (location.hash === "#step-all" && summary.frames > 1) {
  const gl = renderer.getContext();
  const px = new Uint8Array(4);
  const steps = Math.min(100, summary.frames);
  let update = 0;
  let drawn = 0;
  for (let i = 0; i < steps; i++) {
    const f = Math.round((i * (summary.frames - 1)) / Math.max(1, steps - 1));
    const t = performance.now();
    summary.frame = f;
    for (const l of layers) l.show(f);
    const t1 = performance.now();
    render();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px); // wait for the draw to finish
    update += t1 - t;
    drawn += performance.now() - t;
  }
  summary.update_ms_mean = update / steps;
  summary.frame_ms_mean = drawn / steps;
  showFrame(0);
}
summary.ready = true;
publish();
