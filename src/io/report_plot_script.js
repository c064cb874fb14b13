// The reports' interactive plots, inlined into report.html after uPlot (lathectl
// embeds this file at build time). Every time-axis plot of the page gets a uPlot chart; all of
// them share one x range. Data: per series a min/max pyramid (include/lathectl/sim/plot_pyramid.hpp), of which each
// redraw takes, for the visible range, the coarsest level that still gives about one point per
// pixel. Page API for tests and scripts: window.lathectlPlots (setRange, reset, state); the URL
// fragment #range=X0,X1 sets the range on load.
(function () {
  "use strict";
  var el = document.getElementById("lathectl-plot-data");
  if (!el || typeof uPlot === "undefined") return;
  var spec = JSON.parse(el.textContent);

  function floats(b64) {
    var s = atob(b64), n = s.length, u = new Uint8Array(n);
    for (var i = 0; i < n; i++) u[i] = s.charCodeAt(i);
    return new Float32Array(u.buffer);
  }
  var blobs = spec.blobs.map(function (b) {
    return {
      n: b.n, x0: b.x0, x1: b.x1, dx: b.dx, uniform: b.uniform,
      levels: b.levels.map(function (l) {
        return { b: l.b, y: floats(l.y), x: l.x ? floats(l.x) : null };
      })
    };
  });
  // x of value i of a level (see sim/plot_pyramid.hpp for the uniform placement).
  function xAt(blob, lv, i) {
    if (lv.x) return blob.x0 + lv.x[i];
    if (lv.b === 1) return blob.x0 + i * blob.dx;
    var j = i >> 1;
    return blob.x0 + (j * lv.b + ((i & 1) ? 0.75 : 0.25) * lv.b) * blob.dx;
  }
  function lowerBound(blob, lv, x) {  // first i with xAt(i) >= x
    var lo = 0, hi = lv.y.length;
    while (lo < hi) {
      var mid = (lo + hi) >> 1;
      if (xAt(blob, lv, mid) < x) lo = mid + 1; else hi = mid;
    }
    return lo;
  }
  function span(blob) { return blob.n ? [blob.x0, blob.x1] : null; }
  // The visible part of one series at about one point per pixel: [xs, ys, level bucket].
  function slice(blob, x0, x1, pixels) {
    var L = blob.levels, pick = L[0];
    for (var k = L.length - 1; k >= 0; k--) {
      var lv = L[k], a = lowerBound(blob, lv, x0), b = lowerBound(blob, lv, x1);
      pick = lv;
      if (b - a >= pixels) break;
    }
    var i0 = Math.max(0, lowerBound(blob, pick, x0) - 1);
    var i1 = Math.min(pick.y.length, lowerBound(blob, pick, x1) + 1);
    var xs = new Array(i1 - i0), ys = new Array(i1 - i0);
    for (var i = i0; i < i1; i++) {
      var v = pick.y[i];
      xs[i - i0] = xAt(blob, pick, i);
      ys[i - i0] = v === v ? v : null;  // NaN: a gap
    }
    return [xs, ys, pick.b];
  }

  var charts = [], busy = false, full = null, current = null;
  function fmt(v) {
    if (v == null || !isFinite(v)) return "–";
    var a = Math.abs(v);
    return a !== 0 && (a >= 1e6 || a < 1e-3) ? v.toExponential(4) : String(+v.toPrecision(6));
  }
  function dataFor(c, x0, x1) {
    var pixels = Math.max(200, c.u ? c.u.bbox.width / devicePixelRatio : c.host.clientWidth);
    var tables = [], points = 0, finest = Infinity;
    c.p.series.forEach(function (s) {
      var r = slice(blobs[s.blob], x0, x1, pixels);
      tables.push([r[0], r[1]]);
      points += r[0].length;
      finest = Math.min(finest, r[2]);
    });
    c.points = points;
    c.bucket = finest;
    return tables.length === 1 ? tables[0] : uPlot.join(tables);
  }
  function publish() {
    var st = api.state();
    document.documentElement.setAttribute("data-lathectl-range", st.x0 + "," + st.x1);
    charts.forEach(function (c) {
      c.host.setAttribute("data-x0", String(c.u.scales.x.min));
      c.host.setAttribute("data-x1", String(c.u.scales.x.max));
      c.host.setAttribute("data-points", String(c.points));
      c.host.setAttribute("data-bucket", String(c.bucket));
    });
    if (readout) readout.textContent = "x " + fmt(st.x0) + " … " + fmt(st.x1) + " · " +
      st.points + " points plotted" + (st.finestBucket === 1 ? " (recorded samples)" :
      " (min/max of " + st.finestBucket + " samples per point)");
  }
  function setRange(x0, x1) {
    if (!(x1 > x0)) return;
    if (busy) return;
    busy = true;
    current = [x0, x1];
    charts.forEach(function (c) {
      c.u.setData(dataFor(c, x0, x1), false);
      c.u.setScale("x", { min: x0, max: x1 });
    });
    busy = false;
    publish();
  }
  function zoom(f, centre) {
    var r = current || full, c = centre == null ? (r[0] + r[1]) / 2 : centre;
    setRange(c - (c - r[0]) * f, c + (r[1] - c) * f);
  }
  function pan(f) {
    var r = current || full, d = (r[1] - r[0]) * f;
    setRange(r[0] + d, r[1] + d);
  }
  var api = {
    setRange: setRange,
    reset: function () { setRange(full[0], full[1]); },
    zoom: zoom,
    pan: pan,
    state: function () {
      var r = current || full, pts = 0, fb = Infinity;
      charts.forEach(function (c) { pts += c.points; fb = Math.min(fb, c.bucket); });
      return {
        x0: r[0], x1: r[1], points: pts, finestBucket: fb,
        charts: charts.map(function (c) {
          return { plot: c.p.plot, x0: c.u.scales.x.min, x1: c.u.scales.x.max, points: c.points, bucket: c.bucket };
        })
      };
    }
  };
  window.lathectlPlots = api;

  function drawMarkers(u, markers) {
    var ctx = u.ctx, b = u.bbox, r = devicePixelRatio;
    ctx.save();
    ctx.strokeStyle = "#8c959f";
    ctx.fillStyle = "#57606a";
    ctx.lineWidth = r;
    ctx.setLineDash([4 * r, 3 * r]);
    ctx.font = (11 * r) + "px system-ui, sans-serif";
    ctx.textAlign = "right";
    markers.forEach(function (m) {
      var x = Math.round(u.valToPos(m.x, "x", true));
      if (x < b.left || x > b.left + b.width) return;
      ctx.beginPath();
      ctx.moveTo(x, b.top);
      ctx.lineTo(x, b.top + b.height);
      ctx.stroke();
      if (m.label) {
        ctx.save();
        ctx.translate(x - 4 * r, b.top + 6 * r);
        ctx.rotate(-Math.PI / 2);
        ctx.fillText(m.label, 0, 0);
        ctx.restore();
      }
    });
    ctx.restore();
  }

  spec.plots.forEach(function (p) {
    p.series.forEach(function (s) {
      var e = span(blobs[s.blob]);
      if (e) full = full ? [Math.min(full[0], e[0]), Math.max(full[1], e[1])] : e;
    });
    p.markers.forEach(function (m) {
      if (full && isFinite(m.x)) full = [Math.min(full[0], m.x), Math.max(full[1], m.x)];
    });
  });
  if (!full || !(full[1] > full[0])) return;

  var bar = document.createElement("div"), readout = document.createElement("span");
  bar.className = "plot-bar";
  [["−", "zoom out", function () { zoom(2); }], ["+", "zoom in", function () { zoom(0.5); }],
   ["◀", "pan left", function () { pan(-0.25); }], ["▶", "pan right", function () { pan(0.25); }],
   ["Reset", "whole run", function () { api.reset(); }]].forEach(function (b) {
    var btn = document.createElement("button");
    btn.type = "button";
    btn.textContent = b[0];
    btn.title = b[1];
    btn.addEventListener("click", b[2]);
    bar.appendChild(btn);
  });
  var hint = document.createElement("span");
  hint.className = "hint";
  hint.textContent = "drag: zoom · double-click: whole run · shift+wheel: zoom · legend: show/hide";
  readout.className = "readout";
  bar.appendChild(readout);
  bar.appendChild(hint);

  spec.plots.forEach(function (p) {
    var box = document.getElementById("plot-" + p.plot);
    if (!box) return;
    var host = document.createElement("div");
    host.className = "uplot-host";
    box.appendChild(host);
    box.classList.add("live");
    if (!bar.parentNode) box.parentNode.insertBefore(bar, box);
    var c = { p: p, host: host, u: null, points: 0, bucket: 1 };
    var series = [{ label: p.x_label, value: function (u, v) { return fmt(v); } }];
    p.series.forEach(function (s) {
      var o = { label: s.name || " ", stroke: s.color, width: 1.5, value: function (u, v) { return fmt(v); } };
      if (s.dashed) o.dash = [7, 4];
      if (s.points) {
        o.paths = function () { return null; };
        o.points = { show: true, size: 5, fill: s.color, stroke: s.color };
      } else {
        o.points = { show: false };
      }
      series.push(o);
    });
    var opts = {
      title: p.title,
      width: Math.max(320, host.clientWidth || box.clientWidth || 900),
      height: 280,
      scales: { x: { time: false } },
      axes: [{ label: p.x_label, stroke: "#424a53", grid: { stroke: "#e6e9ed" } },
             { label: p.y_label, stroke: "#424a53", grid: { stroke: "#e6e9ed" }, size: 70 }],
      series: series,
      legend: { live: true },
      cursor: {
        sync: { key: "lathectl", setSeries: false },
        drag: { x: true, y: false },
        bind: { dblclick: function () { return function () { api.reset(); return null; }; } }
      },
      hooks: {
        setScale: [function (u, key) {
          if (key !== "x" || busy) return;
          var a = u.scales.x.min, b = u.scales.x.max;
          Promise.resolve().then(function () { setRange(a, b); });
        }],
        draw: [function (u) { drawMarkers(u, p.markers); }]
      }
    };
    c.u = new uPlot(opts, dataFor(c, full[0], full[1]), host);
    c.u.over.addEventListener("wheel", function (e) {
      if (!e.shiftKey) return;
      e.preventDefault();
      var d = e.deltaY || e.deltaX;
      zoom(d > 0 ? 1.25 : 0.8, c.u.posToVal(e.offsetX, "x"));
    }, { passive: false });
    charts.push(c);
  });
  document.documentElement.classList.add("js-plots");
  window.addEventListener("resize", function () {
    charts.forEach(function (c) {
      c.u.setSize({ width: Math.max(320, c.host.clientWidth), height: 280 });
    });
  });
  function fromHash() {
    var m = /(?:^#|&)range=([^,&]+),([^&]+)/.exec(location.hash);
    if (m) setRange(parseFloat(m[1]), parseFloat(m[2])); else setRange(full[0], full[1]);
  }
  window.addEventListener("hashchange", fromHash);
  fromHash();
})();
