// vibss 3-D mode viewer: plain JavaScript on a 2-D canvas with its own orthographic projection.
// Data (SI: m, rad, Hz) come from the JSON block #viewer-data written by vibss/report/viewer.py.
(function () {
  "use strict";
  var data = JSON.parse(document.getElementById("viewer-data").textContent);
  var canvas = document.getElementById("viewer-canvas");
  var select = document.getElementById("viewer-mode");
  var button = document.getElementById("viewer-play");
  var ctx = canvas.getContext("2d");
  var COLORS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf"];
  // corners are numbered by sign bits (4 x + 2 y + z): the six faces as corner loops
  var FACES = [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]];
  var EDGES = [[0, 1], [1, 3], [3, 2], [2, 0], [4, 5], [5, 7], [7, 6], [6, 4], [0, 4], [1, 5], [2, 6], [3, 7]];
  var PERIOD = 2.0;                                    // seconds per animation cycle, whatever the mode
  var W = canvas.width, H = canvas.height;
  var view = { yaw: -0.65, pitch: 0.42, zoom: 1.0 };
  var state = { mode: 0, playing: true, phase: 0, frames: 0, t0: null, drag: null };

  // HiDPI: draw at the device's resolution, show at the nominal size
  var dpr = window.devicePixelRatio || 1;
  canvas.style.width = W + "px";
  canvas.style.maxWidth = "100%";
  canvas.width = Math.round(W * dpr);
  canvas.height = Math.round(H * dpr);

  function fmtHz(hz) { return hz === 0 ? "0 Hz (rigid)" : hz.toFixed(hz < 10 ? 3 : hz < 100 ? 2 : 1) + " Hz"; }

  data.modes.forEach(function (m, i) {
    var opt = document.createElement("option");
    opt.value = String(i);
    opt.textContent = m.n + ": " + fmtHz(m.hz) + ", " + m.label;
    select.appendChild(opt);
    if (state.mode === 0 && m.hz === 0 && i + 1 < data.modes.length) { state.mode = i + 1; }
  });
  select.value = String(state.mode);
  if (data.total > data.modes.length) {
    select.title = "the lowest " + data.modes.length + " of " + data.total + " modes";
    select.insertAdjacentText("afterend", " (lowest " + data.modes.length + " of " + data.total + ")");
  }

  // -- vectors and motion ----------------------------------------------------------------------
  function add(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function mul(a, s) { return [a[0] * s, a[1] * s, a[2] * s]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

  // rigid motion of body i at amplitude s: translation u s, rotation (Rodrigues) by theta s about the cog
  function mover(i, s) {
    if (i < 0) { return function (x) { return x; }; }
    var q = data.modes[state.mode].q[i], cog = data.bodies[i].cog;
    var u = mul(q.slice(0, 3), s), th = mul(q.slice(3, 6), s), phi = Math.sqrt(dot(th, th));
    var k = phi > 0 ? mul(th, 1 / phi) : [0, 0, 0], c = Math.cos(phi), sn = Math.sin(phi);
    return function (x) {
      var r = sub(x, cog);
      var rr = add(add(mul(r, c), mul(cross(k, r), sn)), mul(k, dot(k, r) * (1 - c)));
      return add(add(cog, u), rr);
    };
  }

  // -- projection: yaw about z, then pitch; x right, z up at yaw = pitch = 0 ---------------------
  function project(x) {
    var p = sub(x, data.center), cy = Math.cos(view.yaw), sy = Math.sin(view.yaw);
    var cp = Math.cos(view.pitch), sp = Math.sin(view.pitch);
    var x1 = cy * p[0] - sy * p[1], y1 = sy * p[0] + cy * p[1];
    var s = view.zoom * 0.62 * Math.min(W, H) / data.size;
    return { x: 0.6 * W + s * x1, y: H / 2 + 20 - s * (sp * y1 + cp * p[2]), depth: cp * y1 - sp * p[2] };
  }

  function polyline(pts) {
    ctx.beginPath();
    pts.forEach(function (p, j) { if (j === 0) { ctx.moveTo(p.x, p.y); } else { ctx.lineTo(p.x, p.y); } });
  }

  // spring symbol between two screen points: straight ends, zig-zag in the middle
  function spring(a, b) {
    var dx = b.x - a.x, dy = b.y - a.y, len = Math.sqrt(dx * dx + dy * dy) || 1;
    var nx = -dy / len * 5, ny = dx / len * 5, pts = [a], n = 8;
    for (var j = 0; j <= n; j++) {
      var t = 0.2 + 0.6 * j / n, side = (j === 0 || j === n) ? 0 : (j % 2 ? 1 : -1);
      pts.push({ x: a.x + t * dx + side * nx, y: a.y + t * dy + side * ny });
    }
    pts.push(b);
    polyline(pts);
    ctx.stroke();
  }

  function ground(a) {                                 // a hatched bar under a ground spring's end
    ctx.beginPath();
    ctx.moveTo(a.x - 9, a.y); ctx.lineTo(a.x + 9, a.y);
    for (var j = -9; j <= 6; j += 5) { ctx.moveTo(a.x + j, a.y); ctx.lineTo(a.x + j + 4, a.y + 5); }
    ctx.stroke();
  }

  // -- the scene ---------------------------------------------------------------------------------
  function drawScene(s) {
    var movers = data.bodies.map(function (b, i) { return mover(i, s); });
    ctx.lineWidth = 1;
    ctx.setLineDash([4, 3]);
    ctx.strokeStyle = "#b0b0b0";                        // bodies at rest
    data.bodies.forEach(function (b) {
      var c = b.corners.map(project);
      EDGES.forEach(function (e) { polyline([c[e[0]], c[e[1]]]); ctx.stroke(); });
    });
    ctx.setLineDash([]);
    var faces = [];
    data.bodies.forEach(function (b, i) {
      var c = b.corners.map(movers[i]).map(project);
      FACES.forEach(function (f) {
        var pts = f.map(function (j) { return c[j]; });
        var depth = pts.reduce(function (acc, p) { return acc + p.depth; }, 0) / 4;
        faces.push({ pts: pts, depth: depth, color: COLORS[i % COLORS.length] });
      });
    });
    faces.sort(function (a, b) { return b.depth - a.depth; });      // far faces first
    faces.forEach(function (f) {
      polyline(f.pts);
      ctx.closePath();
      ctx.globalAlpha = 0.28;
      ctx.fillStyle = f.color;
      ctx.fill();
      ctx.globalAlpha = 1;
      ctx.strokeStyle = f.color;
      ctx.stroke();
    });
    data.mounts.forEach(function (m) {                 // rigid arms: dotted from each mount to the cogs it joins
      ctx.setLineDash([2, 3]);
      [m.body, m.to].forEach(function (i) {
        if (i < 0) { return; }
        ctx.strokeStyle = COLORS[i % COLORS.length];
        polyline([project(movers[i](m.point)), project(movers[i](data.bodies[i].cog))]);
        ctx.stroke();
      });
      ctx.setLineDash([]);
    });
    ctx.strokeStyle = "#333";
    ctx.fillStyle = "#111";
    data.mounts.forEach(function (m) {
      var p = project(movers[m.body](m.point));
      if (m.to < 0) {
        var a = project(m.anchor);
        spring(a, p);
        ground(a);
        ctx.beginPath(); ctx.arc(p.x, p.y, 3.5, 0, 2 * Math.PI); ctx.fill();
      } else {
        polyline([project(movers[m.to](m.point)), p]); ctx.stroke();
        diamond(p.x, p.y, 5);
      }
    });
  }

  function diamond(x, y, r) {
    ctx.beginPath(); ctx.moveTo(x, y - r); ctx.lineTo(x + r, y); ctx.lineTo(x, y + r); ctx.lineTo(x - r, y);
    ctx.closePath(); ctx.fill();
  }

  function triad() {                                   // global axes, bottom left
    var o = project(data.center), L = 34, names = ["x", "y", "z"], cols = ["#d62728", "#2ca02c", "#1f77b4"];
    ctx.font = "bold 13px sans-serif";
    var k = L / (view.zoom * 0.62 * Math.min(W, H)), ox = 55, oy = H - 50;   // foreshortened like the model
    for (var j = 0; j < 3; j++) {
      var e = [0, 0, 0];
      e[j] = data.size;
      var t = project(add(data.center, e)), ex = ox + k * (t.x - o.x), ey = oy + k * (t.y - o.y);
      ctx.strokeStyle = ctx.fillStyle = cols[j];
      ctx.lineWidth = 2;
      polyline([{ x: ox, y: oy }, { x: ex, y: ey }]);
      ctx.stroke();
      ctx.fillText(names[j], ex + 0.25 * (ex - ox) - 4, ey + 0.25 * (ey - oy) + 4);
    }
    ctx.lineWidth = 1;
  }

  function legend() {
    var m = data.modes[state.mode], x = 12, y = 22;
    ctx.fillStyle = "#111";
    ctx.font = "bold 15px sans-serif";
    ctx.fillText("Mode " + m.n + " of " + data.total + ": " + fmtHz(m.hz) + ", " + m.label, x, y);
    ctx.font = "12px sans-serif";
    ctx.fillStyle = "#444";
    ctx.fillText("motion scaled: largest displacement " + Math.round(100 * data.fraction) + " % of the model size (" +
                 data.size.toPrecision(3) + " m)", x, y + 18);
    y += 40;
    data.bodies.forEach(function (b, i) {
      ctx.globalAlpha = 0.5; ctx.fillStyle = COLORS[i % COLORS.length]; ctx.fillRect(x, y - 9, 14, 10);
      ctx.globalAlpha = 1; ctx.fillStyle = "#222"; ctx.fillText("body " + b.name, x + 20, y);
      y += 16;
    });
    ctx.fillStyle = "#111";
    ctx.beginPath(); ctx.arc(x + 7, y - 4, 3.5, 0, 2 * Math.PI); ctx.fill();
    ctx.fillStyle = "#222"; ctx.fillText("mount to ground (spring)", x + 20, y);
    y += 16;
    if (data.mounts.some(function (mm) { return mm.to >= 0; })) {
      diamond(x + 7, y - 4, 4.5); ctx.fillText("mount between bodies", x + 20, y);
      y += 16;
    }
    ctx.strokeStyle = "#555"; ctx.setLineDash([2, 3]);
    polyline([{ x: x, y: y - 4 }, { x: x + 14, y: y - 4 }]); ctx.stroke();
    ctx.fillText("rigid arm, mount to cog", x + 20, y);
    y += 16;
    ctx.strokeStyle = "#b0b0b0"; ctx.setLineDash([4, 3]);
    polyline([{ x: x, y: y - 4 }, { x: x + 14, y: y - 4 }]); ctx.stroke(); ctx.setLineDash([]);
    ctx.fillText("at rest", x + 20, y);
  }

  function draw() {
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = "#ffffff";
    ctx.fillRect(0, 0, W, H);
    drawScene(Math.sin(state.phase));
    if (state.frames === 0) {                          // for the browser test: pixels the model drew
      var img = ctx.getImageData(0, 0, canvas.width, canvas.height).data, n = 0;
      for (var j = 0; j < img.length; j += 4) { if (img[j] < 250 || img[j + 1] < 250 || img[j + 2] < 250) { n++; } }
      canvas.setAttribute("data-painted", String(n));
      canvas.setAttribute("data-pixels", String(img.length / 4));
      var r = canvas.getBoundingClientRect();           // where a screenshot finds the canvas [CSS px]
      canvas.setAttribute("data-rect", [r.left + window.scrollX, r.top + window.scrollY, r.width, r.height]
        .map(Math.round).join(","));
    }
    triad();
    legend();
    state.frames += 1;
    canvas.setAttribute("data-frames", String(state.frames));
  }

  function tick(now) {
    if (state.t0 === null) { state.t0 = now; }
    if (state.playing) { state.phase = 2 * Math.PI * ((now - state.t0) / 1000 / PERIOD); draw(); }
    window.requestAnimationFrame(tick);
  }

  // -- interaction -----------------------------------------------------------------------------
  select.addEventListener("change", function () { state.mode = Number(select.value); draw(); });
  button.addEventListener("click", function () {
    state.playing = !state.playing;
    button.textContent = state.playing ? "pause" : "play";
    state.t0 = null;
  });
  canvas.addEventListener("pointerdown", function (e) {
    state.drag = { x: e.clientX, y: e.clientY };
    canvas.setPointerCapture(e.pointerId);
    canvas.style.cursor = "grabbing";
  });
  canvas.addEventListener("pointermove", function (e) {
    if (!state.drag) { return; }
    view.yaw += 0.01 * (e.clientX - state.drag.x);
    view.pitch = Math.max(-1.55, Math.min(1.55, view.pitch + 0.01 * (e.clientY - state.drag.y)));
    state.drag = { x: e.clientX, y: e.clientY };
    draw();
  });
  canvas.addEventListener("pointerup", function () { state.drag = null; canvas.style.cursor = "grab"; });
  canvas.addEventListener("wheel", function (e) {
    e.preventDefault();
    view.zoom = Math.max(0.2, Math.min(8, view.zoom * Math.exp(-0.0015 * e.deltaY)));
    draw();
  }, { passive: false });
  canvas.addEventListener("dblclick", function () { view.yaw = -0.65; view.pitch = 0.42; view.zoom = 1; draw(); });

  state.phase = Math.PI / 2;                           // the first frame shows the largest motion
  draw();
  window.requestAnimationFrame(tick);
})();
