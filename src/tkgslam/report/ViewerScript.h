#pragma once
// JavaScript of the report's 3-D view: plain WebGL (Canvas 2D fallback) drawing the map points,
// keyframe frustums and trajectory, orbit with a drag and zoom with the wheel. It reads the scene
// from <script id="scene" type="application/json"> and, when drawn, records the number of
// non-background pixels in the canvas's data-drawn-pixels attribute (and data-renderer).
namespace tkgslam::report {

inline constexpr const char* kViewerScript = R"JS(
(function () {
  const scene = JSON.parse(document.getElementById('scene').textContent);
  const canvas = document.getElementById('view3d');
  const P = scene.points, T = scene.trajectory, F = scene.frustums;
  // Orbit around the median of the map points (the trajectory's if there is no map).
  const median = (k, stride, arr) => {
    const v = [];
    for (let i = k; i < arr.length; i += stride) v.push(arr[i]);
    v.sort((a, b) => a - b);
    return v.length ? v[Math.floor(v.length / 2)] : 0;
  };
  const src = P.length ? P : T, stride = P.length ? 6 : 3;
  const cx = median(0, stride, src), cy = median(1, stride, src), cz = median(2, stride, src);
  // Frame the bulk of the map: the 90th percentile of the point distances (outliers ignored).
  const dists = [];
  for (let i = 0; i < P.length; i += 6) dists.push(Math.hypot(P[i] - cx, P[i + 1] - cy, P[i + 2] - cz));
  dists.sort((a, b) => a - b);
  const radius = dists.length ? Math.max(0.1, Math.min(10, dists[Math.floor(0.9 * (dists.length - 1))])) : 1;
  let yaw = 0.6, pitch = -0.5, dist = radius * 1.6;
  // Height = -y of the first camera frame (y points down in camera frames).
  let hmin = Infinity, hmax = -Infinity;
  for (let i = 0; i < P.length; i += 6) { hmin = Math.min(hmin, -P[i + 1]); hmax = Math.max(hmax, -P[i + 1]); }
  function heightColour(h) {
    const a = hmax > hmin ? (h - hmin) / (hmax - hmin) : 0.5;
    const f = c => Math.min(1, Math.max(0, 1.5 - Math.abs(4 * a - c)));
    return [f(3), f(2), f(1)];
  }
  // Camera: rotate about y (yaw) then x (pitch), push back by dist; f = focal length in pixels.
  function toCamera(x, y, z) {
    x -= cx; y -= cy; z -= cz;
    const c1 = Math.cos(yaw), s1 = Math.sin(yaw), c2 = Math.cos(pitch), s2 = Math.sin(pitch);
    const x1 = c1 * x + s1 * z, z1 = -s1 * x + c1 * z;
    return [x1, c2 * y - s2 * z1, s2 * y + c2 * z1 + dist];
  }
  const focal = () => canvas.height * 1.2;
  const segments = [];  // frustums and trajectory as line segments: [x, y, z, r, g, b] pairs
  function addPolyline(arr, rgb) {
    for (let i = 3; i < arr.length; i += 3) {
      segments.push(arr[i - 3], arr[i - 2], arr[i - 1], ...rgb, arr[i], arr[i + 1], arr[i + 2], ...rgb);
    }
  }
  for (const f of F) addPolyline(f, [0.96, 0.77, 0.26]);
  addPolyline(T, [1.0, 0.3, 0.3]);
  const points = [];
  for (let i = 0; i < P.length; i += 6) points.push(P[i], P[i + 1], P[i + 2], ...heightColour(-P[i + 1]));

  const gl = canvas.getContext('webgl', {preserveDrawingBuffer: true});
  let draw;
  if (gl) {
    // Plain WebGL: the projection is done in the vertex shader from the same camera model.
    const vs = 'attribute vec3 p; attribute vec3 c; uniform vec3 ctr; uniform vec4 cam; uniform vec2 size;' +
      'varying vec3 col; void main() { vec3 q = p - ctr; float c1 = cos(cam.x), s1 = sin(cam.x), c2 = cos(cam.y), s2 = sin(cam.y);' +
      'float x1 = c1 * q.x + s1 * q.z, z1 = -s1 * q.x + c1 * q.z; float y2 = c2 * q.y - s2 * z1, z2 = s2 * q.y + c2 * z1 + cam.z;' +
      'gl_Position = vec4(2.0 * cam.w * x1 / size.x, -2.0 * cam.w * y2 / size.y, (z2 - 0.001) / 1000.0 * z2, z2);' +
      'gl_PointSize = 3.0; col = c; }';
    const fs = 'precision mediump float; varying vec3 col; void main() { gl_FragColor = vec4(col, 1.0); }';
    const shader = (type, text) => {
      const s = gl.createShader(type); gl.shaderSource(s, text); gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
      return s;
    };
    const prog = gl.createProgram();
    gl.attachShader(prog, shader(gl.VERTEX_SHADER, vs));
    gl.attachShader(prog, shader(gl.FRAGMENT_SHADER, fs));
    gl.linkProgram(prog);
    gl.useProgram(prog);
    const buffer = data => { const b = gl.createBuffer(); gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(data), gl.STATIC_DRAW); return b; };
    const pointBuf = buffer(points), segBuf = buffer(segments);
    const locP = gl.getAttribLocation(prog, 'p'), locC = gl.getAttribLocation(prog, 'c');
    const bind = b => { gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.enableVertexAttribArray(locP); gl.vertexAttribPointer(locP, 3, gl.FLOAT, false, 24, 0);
      gl.enableVertexAttribArray(locC); gl.vertexAttribPointer(locC, 3, gl.FLOAT, false, 24, 12); };
    draw = function () {
      gl.viewport(0, 0, canvas.width, canvas.height);
      gl.clearColor(17 / 255, 17 / 255, 17 / 255, 1); gl.clear(gl.COLOR_BUFFER_BIT);
      gl.uniform3f(gl.getUniformLocation(prog, 'ctr'), cx, cy, cz);
      gl.uniform4f(gl.getUniformLocation(prog, 'cam'), yaw, pitch, dist, focal());
      gl.uniform2f(gl.getUniformLocation(prog, 'size'), canvas.width, canvas.height);
      bind(pointBuf); gl.drawArrays(gl.POINTS, 0, points.length / 6);
      bind(segBuf); gl.drawArrays(gl.LINES, 0, segments.length / 6);
      const px = new Uint8Array(canvas.width * canvas.height * 4);
      gl.readPixels(0, 0, canvas.width, canvas.height, gl.RGBA, gl.UNSIGNED_BYTE, px);
      let drawn = 0;
      for (let i = 0; i < px.length; i += 4) if (px[i] !== 17 || px[i + 1] !== 17 || px[i + 2] !== 17) drawn++;
      canvas.dataset.drawnPixels = drawn;
      canvas.dataset.renderer = 'webgl';
    };
  } else {
    // No WebGL (e.g. an old browser): the same view with Canvas 2D.
    const ctx = canvas.getContext('2d');
    const project = (x, y, z) => { const q = toCamera(x, y, z); if (q[2] < 1e-3) return null;
      return [canvas.width / 2 + focal() * q[0] / q[2], canvas.height / 2 + focal() * q[1] / q[2]]; };
    const css = c => 'rgb(' + c.map(v => Math.round(255 * v)).join(',') + ')';
    draw = function () {
      ctx.fillStyle = '#111'; ctx.fillRect(0, 0, canvas.width, canvas.height);
      for (let i = 0; i < points.length; i += 6) {
        const p = project(points[i], points[i + 1], points[i + 2]);
        if (!p) continue;
        ctx.fillStyle = css(points.slice(i + 3, i + 6)); ctx.fillRect(p[0] - 1.5, p[1] - 1.5, 3, 3);
      }
      for (let i = 0; i < segments.length; i += 12) {
        const a = project(segments[i], segments[i + 1], segments[i + 2]);
        const b = project(segments[i + 6], segments[i + 7], segments[i + 8]);
        if (!a || !b) continue;
        ctx.strokeStyle = css(segments.slice(i + 3, i + 6)); ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
      }
      const img = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
      let drawn = 0;
      for (let i = 0; i < img.length; i += 4) if (img[i] !== 17 || img[i + 1] !== 17 || img[i + 2] !== 17) drawn++;
      canvas.dataset.drawnPixels = drawn;
      canvas.dataset.renderer = 'canvas2d';
    };
  }
  let drag = null;
  canvas.addEventListener('mousedown', e => { drag = [e.clientX, e.clientY]; });
  window.addEventListener('mouseup', () => { drag = null; });
  window.addEventListener('mousemove', e => {
    if (!drag) return;
    yaw += (e.clientX - drag[0]) * 0.01; pitch += (e.clientY - drag[1]) * 0.01;
    pitch = Math.max(-1.5, Math.min(1.5, pitch)); drag = [e.clientX, e.clientY]; draw();
  });
  canvas.addEventListener('wheel', e => { e.preventDefault(); dist *= e.deltaY > 0 ? 1.1 : 0.9; draw(); });
  draw();
})();
)JS";

}  // namespace tkgslam::report
