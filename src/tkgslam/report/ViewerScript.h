#pragma once
// JavaScript of the report's 3-D view: a Canvas 2D point/line renderer with orbit (drag) and zoom
// (wheel). It reads the scene from <script id="scene" type="application/json"> and, when drawn,
// records the number of non-background pixels in the canvas's data-drawn-pixels attribute.
namespace tkgslam::report {

inline constexpr const char* kViewerScript = R"JS(
(function () {
  const scene = JSON.parse(document.getElementById('scene').textContent);
  const canvas = document.getElementById('view3d');
  const ctx = canvas.getContext('2d');
  const P = scene.points, T = scene.trajectory, F = scene.frustums;
  // Orbit around the median of the map points (the trajectory's mean if there is no map).
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
  let radius = dists.length ? Math.max(0.1, Math.min(10, dists[Math.floor(0.9 * (dists.length - 1))])) : 1;
  let yaw = 0.6, pitch = -0.5, dist = radius * 1.6;
  // Height = -y of the first camera frame (y points down in camera frames).
  let hmin = Infinity, hmax = -Infinity;
  for (let i = 0; i < P.length; i += 6) { hmin = Math.min(hmin, -P[i + 1]); hmax = Math.max(hmax, -P[i + 1]); }
  function heightColour(h) {
    const a = hmax > hmin ? (h - hmin) / (hmax - hmin) : 0.5;
    const r = Math.round(255 * Math.min(1, Math.max(0, 1.5 - Math.abs(4 * a - 3))));
    const g = Math.round(255 * Math.min(1, Math.max(0, 1.5 - Math.abs(4 * a - 2))));
    const b = Math.round(255 * Math.min(1, Math.max(0, 1.5 - Math.abs(4 * a - 1))));
    return 'rgb(' + r + ',' + g + ',' + b + ')';
  }
  function project(x, y, z) {
    x -= cx; y -= cy; z -= cz;
    const c1 = Math.cos(yaw), s1 = Math.sin(yaw), c2 = Math.cos(pitch), s2 = Math.sin(pitch);
    const x1 = c1 * x + s1 * z, z1 = -s1 * x + c1 * z;
    const y2 = c2 * y - s2 * z1, z2 = s2 * y + c2 * z1 + dist;
    if (z2 < 1e-3) return null;
    const f = canvas.height * 1.2;
    return [canvas.width / 2 + f * x1 / z2, canvas.height / 2 + f * y2 / z2];
  }
  function polyline(arr, colour, width) {
    ctx.strokeStyle = colour; ctx.lineWidth = width; ctx.beginPath();
    let started = false;
    for (let i = 0; i < arr.length; i += 3) {
      const p = project(arr[i], arr[i + 1], arr[i + 2]);
      if (!p) { started = false; continue; }
      if (started) ctx.lineTo(p[0], p[1]); else ctx.moveTo(p[0], p[1]);
      started = true;
    }
    ctx.stroke();
  }
  function draw() {
    ctx.fillStyle = '#111'; ctx.fillRect(0, 0, canvas.width, canvas.height);
    for (let i = 0; i < P.length; i += 6) {
      const p = project(P[i], P[i + 1], P[i + 2]);
      if (!p) continue;
      ctx.fillStyle = heightColour(-P[i + 1]);
      ctx.fillRect(p[0] - 1.5, p[1] - 1.5, 3, 3);
    }
    for (const f of F) polyline(f, '#f5c542', 1);
    polyline(T, '#ff4d4d', 2);
    const img = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
    let drawn = 0;
    for (let i = 0; i < img.length; i += 4) if (img[i] !== 17 || img[i + 1] !== 17 || img[i + 2] !== 17) drawn++;
    canvas.dataset.drawnPixels = drawn;
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
