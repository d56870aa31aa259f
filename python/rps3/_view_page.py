"""The self-contained HTML page of rps3.view.html: its template, whose
__TITLE__, __DATA__ and similar markers view.html fills (no library, no
network; the data block holds what is drawn)."""

_PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>__TITLE__</title>
<style>
body { font-family: sans-serif; margin: 0.5em; background: #fff; }
canvas { border: 1px solid #ccc; cursor: grab; }
#bar { margin: 0.3em 0; } #label { font-family: monospace; }
.legend span { margin-right: 1em; } .failed { color: #c00; }
</style></head>
<body>
<div id="bar"><button id="play">pause</button>
<input id="slider" type="range" min="0" max="0" value="0" style="width: 60%"></div>
<div id="label"></div>
<canvas id="view" width="720" height="540"></canvas>
<div class="legend">__LEGEND__</div>
<p>Drag to turn the view, wheel to zoom. Base frame: X towards pin 1, Z up; lengths in metres.</p>
<script id="rps3-data" type="application/json">__DATA__</script>
<script>
"use strict";
window.addEventListener("error", function (e) {
  document.body.dataset.error = String(e.message);
});
(function () {
  var D = JSON.parse(document.getElementById("rps3-data").textContent);
  var cv = document.getElementById("view"), g = cv.getContext("2d");
  var slider = document.getElementById("slider"), label = document.getElementById("label");
  var play = document.getElementById("play");
  // the figures' view at first (matplotlib's azimuth -60 deg, elevation 22 deg)
  var n = D.frames.length, k = 0, running = n > 1, az = -Math.PI / 6, el = 0.384, zoom = 1;
  slider.max = String(n - 1);
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function add(a, b, s) { return [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]; }
  // orthographic view from above: turn about Z by az (x to the right, y
  // away from the viewer), tilt by el; screen up is Z
  function proj(p) {
    var q = sub(p, D.centre), ca = Math.cos(az), sa = Math.sin(az);
    var x = ca * q[0] - sa * q[1], y = sa * q[0] + ca * q[1];
    var ce = Math.cos(el), se = Math.sin(el), s = zoom * 0.3 * cv.height / D.half;
    return [cv.width / 2 + s * x, cv.height / 2 - s * (ce * q[2] + se * y)];
  }
  function line(pts, colour, width, close) {
    g.beginPath();
    for (var i = 0; i < pts.length; i++) {
      var p = proj(pts[i]);
      if (i === 0) g.moveTo(p[0], p[1]); else g.lineTo(p[0], p[1]);
    }
    if (close) g.closePath();
    g.strokeStyle = colour; g.lineWidth = width; g.stroke();
  }
  function fill(pts, colour) {
    g.beginPath();
    pts.forEach(function (q, i) {
      var p = proj(q); if (i) g.lineTo(p[0], p[1]); else g.moveTo(p[0], p[1]);
    });
    g.closePath(); g.globalAlpha = 0.35; g.fillStyle = colour; g.fill(); g.globalAlpha = 1;
  }
  function draw() {
    var f = D.frames[k], C = D.colours, i;
    g.clearRect(0, 0, cv.width, cv.height);
    fill(D.pin, C.base); line(D.pin, C.base, 2, true);
    for (i = 0; i < 3; i++)
      line([add(D.pin[i], D.axis[i], -D.pinlen), add(D.pin[i], D.axis[i], D.pinlen)],
           C.pin, 5, false);
    label.textContent = (D.times ? "t = " + D.times[k].toFixed(3) + " s  " : "") +
      "frame " + (k + 1) + "/" + n + "  " + f.text;
    label.className = f.ok ? "" : "failed";
    if (f.ok) {
      for (i = 0; i < 3; i++) {
        line([D.pin[i], f.end[i]], C.barrel, 8, false);
        line([f.end[i], f.ball[i]], C.piston, 4, false);
      }
      fill(f.ball, C.platform); line(f.ball, C.platform, 2, true);
      if (f.ref) { g.setLineDash([6, 4]); line(f.ref, C.reference, 2, true); g.setLineDash([]); }
      for (i = 0; i < 3; i++) {
        var p = proj(f.ball[i]);
        g.beginPath(); g.arc(p[0], p[1], 5, 0, 2 * Math.PI); g.fillStyle = C.ball; g.fill();
      }
    }
    slider.value = String(k);
    document.body.dataset.frame = String(k);
  }
  slider.addEventListener("input", function () { k = +slider.value; draw(); });
  play.addEventListener("click", function () {
    running = !running; play.textContent = running ? "pause" : "play";
  });
  var drag = null;
  cv.addEventListener("mousedown", function (e) { drag = [e.clientX, e.clientY]; });
  window.addEventListener("mouseup", function () { drag = null; });
  window.addEventListener("mousemove", function (e) {
    if (!drag) return;
    az += (e.clientX - drag[0]) * 0.01;
    el = Math.max(-1.5, Math.min(1.5, el + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY]; draw();
  });
  cv.addEventListener("wheel", function (e) {
    e.preventDefault(); zoom *= Math.exp(-e.deltaY * 0.001); draw();
  }, {passive: false});
  draw();
  // how many pixels the first drawing inked: the page's own check
  var px = g.getImageData(0, 0, cv.width, cv.height).data, inked = 0;
  for (var j = 3; j < px.length; j += 4) if (px[j] > 0) inked++;
  document.body.dataset.inked = String(inked);
  document.body.dataset.frames = String(n);
  document.body.dataset.ready = "1";
  // a timer, not requestAnimationFrame: the page plays at the file's fps
  // wherever it is shown, and a headless browser's virtual time runs timers
  // deterministically where it may never paint a frame
  var played = 0;
  function tick() {
    if (running) { k = (k + 1) % n; played++; draw(); }
    document.body.dataset.played = String(played);
    window.setTimeout(tick, 1000 / D.fps);
  }
  window.setTimeout(tick, 1000 / D.fps);
})();
</script></body></html>
"""
