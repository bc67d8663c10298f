// The row's assembly.glb in a browser: a small WebGL2 viewer with no library and no network, so the page
// aero-env sheet writes (assembly.html) opens from the disk anywhere. It reads the binary glTF embedded in the
// page, walks its node tree (each node's matrix, column-major), and draws every mesh with flat shading in its
// material's colour. Drag to turn, wheel to zoom; the panel hides a group (a frame, the robot, the stand) and
// explodes the parts across the row. window.viewer is what the tests and the picture script drive.
"use strict";
(function () {
  const canvas = document.getElementById("view");
  const gl = canvas.getContext("webgl2", { antialias: true, preserveDrawingBuffer: true });
  if (!gl) { document.getElementById("status").textContent = "This browser has no WebGL2."; return; }

  // ---- the glTF binary: header, JSON chunk, BIN chunk ----
  const bytes = Uint8Array.from(atob(document.getElementById("model").textContent.trim()), c => c.charCodeAt(0));
  const head = new DataView(bytes.buffer);
  const jsonLength = head.getUint32(12, true);
  const gltf = JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + jsonLength)));
  const binStart = 20 + jsonLength + 8;
  const TYPES = { 5126: Float32Array, 5125: Uint32Array, 5123: Uint16Array, 5121: Uint8Array };
  const WIDTH = { SCALAR: 1, VEC3: 3, VEC4: 4 };
  function accessor(i) {
    const a = gltf.accessors[i], view = gltf.bufferViews[a.bufferView], T = TYPES[a.componentType];
    const start = binStart + (view.byteOffset || 0) + (a.byteOffset || 0);
    return new T(bytes.buffer.slice(start, start + a.count * WIDTH[a.type] * T.BYTES_PER_ELEMENT));
  }
  function multiply(a, b) {  // 4x4, column-major
    const out = new Array(16);
    for (let c = 0; c < 4; c++) for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      out[c * 4 + r] = s;
    }
    return out;
  }
  const IDENTITY = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];

  // ---- every mesh in world coordinates, flat normals, under its top-level group ----
  const meshes = [], groups = [];
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  function walk(index, parent, group) {
    const node = gltf.nodes[index];
    const world = multiply(parent, node.matrix || IDENTITY);
    if (node.mesh !== undefined) {
      for (const prim of gltf.meshes[node.mesh].primitives) {
        const pos = accessor(prim.attributes.POSITION), idx = accessor(prim.indices);
        const material = prim.material !== undefined ? gltf.materials[prim.material] : {};
        const colour = ((material.pbrMetallicRoughness || {}).baseColorFactor || [0.8, 0.8, 0.8, 1]).slice(0, 3);
        const v = new Float32Array(idx.length * 3), n = new Float32Array(idx.length * 3);
        const centre = [0, 0, 0];
        for (let t = 0; t < idx.length; t += 3) {
          const p = [];
          for (let k = 0; k < 3; k++) {
            const i = idx[t + k] * 3, x = pos[i], y = pos[i + 1], z = pos[i + 2];
            const w = [0, 1, 2].map(r => world[r] * x + world[4 + r] * y + world[8 + r] * z + world[12 + r]);
            p.push(w);
            for (let r = 0; r < 3; r++) {
              v[(t + k) * 3 + r] = w[r]; lo[r] = Math.min(lo[r], w[r]); hi[r] = Math.max(hi[r], w[r]);
              centre[r] += w[r] / idx.length;
            }
          }
          const e1 = p[1].map((c, r) => c - p[0][r]), e2 = p[2].map((c, r) => c - p[0][r]);
          const nx = e1[1] * e2[2] - e1[2] * e2[1], ny = e1[2] * e2[0] - e1[0] * e2[2];
          const nz = e1[0] * e2[1] - e1[1] * e2[0];
          const len = Math.hypot(nx, ny, nz) || 1;
          for (let k = 0; k < 3; k++) n.set([nx / len, ny / len, nz / len], (t + k) * 3);
        }
        const buffers = [v, n].map(data => {
          const b = gl.createBuffer();
          gl.bindBuffer(gl.ARRAY_BUFFER, b);
          gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
          return b;
        });
        meshes.push({ name: node.name, group, colour, centre, count: idx.length, buffers });
      }
    }
    for (const child of node.children || []) walk(child, world, group);
  }
  for (const root of gltf.scenes[gltf.scene || 0].nodes) {
    groups.push(gltf.nodes[root].name);
    walk(root, IDENTITY, gltf.nodes[root].name);
  }

  // ---- shading: one directional light and some ambient ----
  function shader(type, source) {
    const s = gl.createShader(type); gl.shaderSource(s, source); gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  }
  const program = gl.createProgram();
  gl.attachShader(program, shader(gl.VERTEX_SHADER, `#version 300 es
    in vec3 position; in vec3 normal; uniform mat4 viewProjection; uniform vec3 offset; out vec3 n;
    void main() { n = normal; gl_Position = viewProjection * vec4(position + offset, 1.0); }`));
  gl.attachShader(program, shader(gl.FRAGMENT_SHADER, `#version 300 es
    precision mediump float; in vec3 n; uniform vec3 colour; uniform vec3 light; out vec4 fragment;
    void main() { float d = abs(dot(normalize(n), light)); fragment = vec4(colour * (0.35 + 0.65 * d), 1.0); }`));
  gl.linkProgram(program);
  const at = name => gl.getUniformLocation(program, name);

  const size = hi.map((h, r) => h - lo[r]);
  const state = { yaw: -0.6, pitch: 0.35, distance: 1.2 * Math.max(...size), explode: 1.0, hidden: new Set(),
                  target: hi.map((h, r) => (h + lo[r]) / 2) };

  function viewProjection() {
    const aspect = canvas.width / canvas.height, f = 1 / Math.tan(0.5 * 0.6), near = state.distance / 100;
    const far = state.distance * 10;
    const cp = Math.cos(state.pitch), d = state.distance, t = state.target;
    const eye = [t[0] + d * cp * Math.sin(state.yaw), t[1] + d * Math.sin(state.pitch),
                 t[2] + d * cp * Math.cos(state.yaw)];
    const z = eye.map((e, r) => e - state.target[r]), zl = Math.hypot(...z), zz = z.map(c => c / zl);
    const x = [zz[2], 0, -zz[0]], xl = Math.hypot(...x), xx = x.map(c => c / xl);
    const yy = [zz[1] * xx[2] - zz[2] * xx[1], zz[2] * xx[0] - zz[0] * xx[2], zz[0] * xx[1] - zz[1] * xx[0]];
    const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const view = [xx[0], yy[0], zz[0], 0, xx[1], yy[1], zz[1], 0, xx[2], yy[2], zz[2], 0,
                  -dot(xx, eye), -dot(yy, eye), -dot(zz, eye), 1];
    const projection = [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) / (near - far), -1,
                        0, 0, 2 * far * near / (near - far), 0];
    return multiply(projection, view);
  }

  function draw() {
    const w = canvas.clientWidth * devicePixelRatio, h = canvas.clientHeight * devicePixelRatio;
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.clearColor(1, 1, 1, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.useProgram(program);
    gl.uniformMatrix4fv(at("viewProjection"), false, viewProjection());
    gl.uniform3fv(at("light"), [0.3, 0.8, 0.52]);
    const positionAt = gl.getAttribLocation(program, "position"), normalAt = gl.getAttribLocation(program, "normal");
    for (const m of meshes) {
      if (state.hidden.has(m.group)) continue;
      // exploded: each part moved across the row in proportion to how far across it sits
      gl.uniform3fv(at("offset"), [0, 0, m.centre[2] * (state.explode - 1)]);
      gl.uniform3fv(at("colour"), m.colour);
      [positionAt, normalAt].forEach((loc, k) => {
        gl.bindBuffer(gl.ARRAY_BUFFER, m.buffers[k]); gl.enableVertexAttribArray(loc);
        gl.vertexAttribPointer(loc, 3, gl.FLOAT, false, 0, 0);
      });
      gl.drawArrays(gl.TRIANGLES, 0, m.count);
    }
  }

  // ---- the panel and the mouse ----
  const panel = document.getElementById("groups");
  for (const g of groups) {
    const label = document.createElement("label"), box = document.createElement("input");
    box.type = "checkbox"; box.checked = true; box.dataset.group = g;
    box.onchange = () => { box.checked ? state.hidden.delete(g) : state.hidden.add(g); draw(); };
    label.append(box, " " + g); panel.append(label, document.createElement("br"));
  }
  const explode = document.getElementById("explode");
  explode.oninput = () => { state.explode = +explode.value; draw(); };
  let drag = null;
  canvas.onmousedown = e => { drag = [e.clientX, e.clientY]; };
  window.onmouseup = () => { drag = null; };
  window.onmousemove = e => {
    if (!drag) return;
    state.yaw -= (e.clientX - drag[0]) * 0.01;
    state.pitch = Math.max(-1.5, Math.min(1.5, state.pitch + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY]; draw();
  };
  canvas.onwheel = e => { e.preventDefault(); state.distance *= Math.exp(e.deltaY * 0.001); draw(); };
  window.onresize = draw;
  draw();
  document.getElementById("status").textContent =
    `${groups.length} groups, ${meshes.length} parts, ${meshes.reduce((s, m) => s + m.count / 3, 0)} triangles`;
  window.viewer = {
    ready: true, groups, parts: meshes.map(m => m.name), triangles: meshes.reduce((s, m) => s + m.count / 3, 0),
    bounds: [lo, hi],
    set(options) {  // {yaw, pitch, distance, target: [x, y, z], explode, hidden: [group, ...]}
      for (const k of ["yaw", "pitch", "distance", "target", "explode"]) {
        if (options[k] !== undefined) state[k] = options[k];
      }
      if (options.hidden) state.hidden = new Set(options.hidden);
      explode.value = state.explode;
      for (const box of panel.querySelectorAll("input")) box.checked = !state.hidden.has(box.dataset.group);
      draw();
    },
  };
})();
