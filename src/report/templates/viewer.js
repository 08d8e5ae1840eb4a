// The viewer (report::viewer): two cells A and B chosen over the run's axes, compared side by
// side, with a wipe or by flicker, a map over them, and a magnifier reading pixels.js. The URL
// fragment holds the whole view. No network: every file is a sibling under the run folder.
(function () {
  'use strict';
  var D = window.SHADEMATRIX_VIEWER;
  var $ = function (id) { return document.getElementById(id); };
  if (!D) {
    $('summary').textContent = 'viewer-data.js is missing: run `shadematrix report DIR` to rebuild the pages.';
    return;
  }
  var axes = D.axes, cells = D.cells;
  var AXIS = {};
  axes.forEach(function (a, k) { AXIS[a.name] = k; });
  var shown = [];
  axes.forEach(function (a, k) { if (a.values.length > 1) shown.push(k); });
  var index = new Map();
  cells.forEach(function (c, i) { index.set(c[1].join(','), i); });

  var state = {
    a: cells.length ? cells[0][1].slice() : axes.map(function () { return 0; }),
    b: null, link: true, mode: 'side', overlay: 'none', opacity: 0.6, zoom: 2, wipe: 0.5,
    px: null, flickerB: false, term: 'image', bref: false
  };
  // The picture of cell i shown: its image, or the chosen term layer where the cell has layers;
  // `ref`: the cell's own reference (its truth, or its supersampled render) instead.
  function picture(i, ref) {
    if (ref) return cellDir(i) + '/reference.png';
    if (state.term !== 'image' && (cells[i][7] & 4)) return cellDir(i) + '/terms/' + state.term + '.png';
    return cellDir(i) + '/image.png';
  }
  state.b = state.a.slice();
  // B starts as A in another pipeline where the run has one.
  if (AXIS.pipeline !== undefined) {
    var p = AXIS.pipeline;
    for (var step = 1; step < axes[p].values.length; step++) {
      var v = state.a.slice();
      v[p] = (state.a[p] + step) % axes[p].values.length;
      if (index.has(v.join(','))) { state.b = v; break; }
    }
  }

  function cellDir(i) { return 'cells/' + encodeURIComponent(cells[i][0]); }
  function valueOf(side, name) { var k = AXIS[name]; return axes[k].values[state[side][k]]; }

  // The cell at `values`, or why there is none.
  function resolve(values) {
    var i = index.get(values.join(','));
    if (i !== undefined) return { cell: i };
    var sel = {};
    axes.forEach(function (a, k) { sel[a.name] = a.values[values[k]]; });
    for (var n = 0; n < D.pruned.length; n++) {
      var p = D.pruned[n];
      if (p.axes.every(function (av) { return sel[av[0]] === av[1]; })) {
        return { why: 'pruned (' + p.description + '): ' + p.reason, pruned: true };
      }
    }
    return { why: 'no cell with these values in this run: the matrix does not sweep them together, or a filter or shard left it out' };
  }

  // Where `side`'s values name no cell and no pruned combination explains why, move the other
  // axes to the nearest rendered cell that keeps the axes in `held` (most recently chosen first;
  // when none keeps them all, the last is let go): fewest axes changed, then the smallest slider
  // moves. A preset fixes metallic and a composition its key light, so sliders snap to what exists.
  function snap(side, held) {
    var want = state[side];
    var r = resolve(want);
    if (r.cell !== undefined || r.pruned) return;
    for (var keep = held.length; keep >= 0; keep--) {
      var best = -1, bestCost = Infinity;
      for (var i = 0; i < cells.length; i++) {
        var v = cells[i][1], ok = true;
        for (var h = 0; h < keep; h++) if (v[held[h]] !== want[held[h]]) { ok = false; break; }
        if (!ok) continue;
        var cost = 0;
        for (var k = 0; k < v.length && cost < bestCost; k++) {
          if (v[k] !== want[k]) cost += 1000 + Math.abs(v[k] - want[k]);
        }
        if (cost < bestCost) { bestCost = cost; best = i; }
      }
      if (best >= 0) { state[side] = cells[best][1].slice(); return; }
    }
  }

  // ---- controls ----
  var controls = { a: {}, b: {} };
  function makeControl(side, k) {
    var a = axes[k], el, out = null;
    if (a.kind !== 'choice') {
      el = document.createElement('input');
      el.type = 'range'; el.min = 0; el.max = a.values.length - 1; el.step = 1;
      out = document.createElement('output');
    } else {
      el = document.createElement('select');
      a.values.forEach(function (v, i) {
        var o = document.createElement('option'); o.value = i; o.textContent = v; el.appendChild(o);
      });
    }
    el.id = side + '-' + a.name;
    el.dataset.axis = a.name;
    el.addEventListener('input', function () {
      state[side][k] = +el.value;
      snap(side, [k]);
      if (side === 'a' && state.link && a.kind !== 'choice') { state.b[k] = state.a[k]; snap('b', [k]); }
      update();
    });
    controls[side][k] = { el: el, out: out };
    var td = document.createElement('td');
    td.appendChild(el);
    if (out) td.appendChild(out);
    return td;
  }
  var tbody = $('axes');
  shown.forEach(function (k) {
    var tr = document.createElement('tr');
    var th = document.createElement('th'); th.textContent = axes[k].name.replace('_', ' ');
    tr.appendChild(th);
    tr.appendChild(makeControl('a', k));
    tr.appendChild(makeControl('b', k));
    tbody.appendChild(tr);
  });
  if (!shown.length) tbody.innerHTML = '<tr><td colspan="3">one cell: nothing to choose</td></tr>';

  $('bref').addEventListener('change', function () { state.bref = $('bref').checked; update(); });
  $('link').addEventListener('change', function () {
    state.link = $('link').checked;
    if (state.link) shown.forEach(function (k) { if (axes[k].kind !== 'choice') state.b[k] = state.a[k]; });
    update();
  });
  ['side', 'wipe', 'flicker'].forEach(function (m) {
    $('mode-' + m).addEventListener('click', function () {
      if (m === 'flicker' && state.mode === 'flicker') state.flickerB = !state.flickerB;
      state.mode = m; update();
    });
  });
  $('overlay').addEventListener('input', function () { state.overlay = $('overlay').value; update(); });
  (D.terms || []).forEach(function (t) {
    var o = document.createElement('option'); o.value = t; o.textContent = t.replace(/_/g, ' ');
    $('term').appendChild(o);
  });
  $('term-bar').hidden = !(D.terms || []).length;
  $('term').addEventListener('input', function () { state.term = $('term').value; update(); });
  $('opacity').addEventListener('input', function () { state.opacity = +$('opacity').value; update(); });
  $('zoom').addEventListener('input', function () { state.zoom = +$('zoom').value; update(); });
  document.addEventListener('keydown', function (e) {
    if ((e.key === 'f' || e.key === 'F') && !e.ctrlKey && !e.metaKey && !e.altKey) {
      if (state.mode !== 'flicker') state.mode = 'flicker'; else state.flickerB = !state.flickerB;
      update();
    }
  });

  // ---- pixels.js ----
  var pixelCache = new Map(), pendingPixels = null;
  window.shadematrixPixels = function (obj) { pendingPixels = obj; };
  function inflate(b64) {
    var bin = atob(b64), bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    var stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate'));
    return new Response(stream).arrayBuffer().then(function (b) { return new Uint8Array(b); });
  }
  function halfToFloat(h) {
    var s = (h & 0x8000) ? -1 : 1, e = (h >> 10) & 0x1f, f = h & 0x3ff;
    if (e === 0) return s * f * Math.pow(2, -24);
    if (e === 31) return f ? NaN : s * Infinity;
    return s * Math.pow(2, e - 15) * (1 + f / 1024);
  }
  // pixels.js stores each channel as wrapping differences from the previous value (images::pixels).
  function decode(obj) {
    return Promise.all([inflate(obj.srgb_planes), inflate(obj.linear_planes)]).then(function (planes) {
      var n = obj.width * obj.height, ds = planes[0], lin = planes[1];
      var srgb = new Uint8Array(3 * n), linear = new Float32Array(3 * n);
      var view = new DataView(new ArrayBuffer(4));
      for (var c = 0; c < 3; c++) {
        var s = 0, bits = 0;
        for (var i = 0; i < n; i++) {
          s = (s + ds[c * n + i]) & 0xff;
          srgb[c * n + i] = s;
          if (obj.linear === 'half') {
            bits = (bits + ((lin[2 * c * n + i] << 8) | lin[(2 * c + 1) * n + i])) & 0xffff;
            linear[3 * i + c] = halfToFloat(bits);
          } else {
            var d = ((lin[4 * c * n + i] << 24) | (lin[(4 * c + 1) * n + i] << 16) |
              (lin[(4 * c + 2) * n + i] << 8) | lin[(4 * c + 3) * n + i]) >>> 0;
            bits = (bits + d) >>> 0;
            view.setUint32(0, bits);
            linear[3 * i + c] = view.getFloat32(0);
          }
        }
      }
      return { width: obj.width, height: obj.height, srgb: srgb, linear: linear, n: n };
    });
  }
  function loadPixels(i) {
    if (pixelCache.has(i)) return pixelCache.get(i);
    var p = (cells[i][7] & 2) === 0 ? Promise.resolve(null) : new Promise(function (res) {
      var s = document.createElement('script');
      s.src = cellDir(i) + '/pixels.js';
      s.onload = function () {
        var obj = pendingPixels; pendingPixels = null; s.remove();
        if (obj) decode(obj).then(res, function () { res(null); }); else res(null);
      };
      document.head.appendChild(s);
    });
    pixelCache.set(i, p);
    return p;
  }
  function pixelText(px, x, y) {
    if (!px) return 'no pixels.js ([outputs] pixels = false)';
    var i = y * px.width + x, n = px.n;
    var s = [px.srgb[i], px.srgb[n + i], px.srgb[2 * n + i]];
    var l = [px.linear[3 * i], px.linear[3 * i + 1], px.linear[3 * i + 2]];
    return { srgb: s, linear: l, text: 'sRGB ' + s.join(' ') + '   linear ' + l.map(function (v) { return v.toPrecision(5); }).join(' ') };
  }

  // SSIM of A against B over the displayed images' luma, exactly as compare::ssim computes it
  // (scikit-image's Gaussian SSIM: 11 taps, σ = 1.5, scipy's reflect boundary, K1 = 0.01,
  // K2 = 0.03, the mean over the window-valid region), in the same order of operations.
  var SSIM_RADIUS = 5;
  var ssimKernel = (function () {
    var k = [], sum = 0;
    for (var i = 0; i <= 2 * SSIM_RADIUS; i++) { var x = i - SSIM_RADIUS; k.push(Math.exp(-0.5 * x * x / (1.5 * 1.5))); }
    for (i = 0; i < k.length; i++) sum += k[i];
    return k.map(function (w) { return w / sum; });
  })();
  function reflect(i, n) { var p = 2 * n, m = ((i % p) + p) % p; return m < n ? m : p - 1 - m; }
  function gaussian(src, w, h) {
    var tmp = new Float64Array(w * h), out = new Float64Array(w * h), x, y, j, acc;
    for (y = 0; y < h; y++) for (x = 0; x < w; x++) {
      acc = 0;
      for (j = 0; j < ssimKernel.length; j++) acc += ssimKernel[j] * src[y * w + reflect(x + j - SSIM_RADIUS, w)];
      tmp[y * w + x] = acc;
    }
    for (y = 0; y < h; y++) for (x = 0; x < w; x++) {
      acc = 0;
      for (j = 0; j < ssimKernel.length; j++) acc += ssimKernel[j] * tmp[reflect(y + j - SSIM_RADIUS, h) * w + x];
      out[y * w + x] = acc;
    }
    return out;
  }
  function ssim(A, B) {
    var w = A.width, h = A.height, n = A.n;
    if (B.width !== w || B.height !== h) return { why: 'A and B differ in size' };
    if (w < 2 * SSIM_RADIUS + 1 || h < 2 * SSIM_RADIUS + 1) return { why: 'smaller than the 11×11 SSIM window' };
    var luma = function (P) {
      var l = new Float64Array(n);
      for (var i = 0; i < n; i++) l[i] = (0.2126 * P.srgb[i] + 0.7152 * P.srgb[n + i] + 0.0722 * P.srgb[2 * n + i]) / 255;
      return l;
    };
    var a = luma(A), b = luma(B), aa = new Float64Array(n), bb = new Float64Array(n), ab = new Float64Array(n);
    for (var i = 0; i < n; i++) { aa[i] = a[i] * a[i]; bb[i] = b[i] * b[i]; ab[i] = a[i] * b[i]; }
    var ux = gaussian(a, w, h), uy = gaussian(b, w, h), uxx = gaussian(aa, w, h), uyy = gaussian(bb, w, h), uxy = gaussian(ab, w, h);
    var c1 = 0.01 * 0.01, c2 = 0.03 * 0.03, map = new Float64Array(n);
    for (i = 0; i < n; i++) {
      var vx = uxx[i] - ux[i] * ux[i], vy = uyy[i] - uy[i] * uy[i], vxy = uxy[i] - ux[i] * uy[i];
      map[i] = (2 * ux[i] * uy[i] + c1) * (2 * vxy + c2) / ((ux[i] * ux[i] + uy[i] * uy[i] + c1) * (vx + vy + c2));
    }
    var sum = 0, count = 0;
    for (var y = SSIM_RADIUS; y < h - SSIM_RADIUS; y++) for (var x = SSIM_RADIUS; x < w - SSIM_RADIUS; x++) { sum += map[y * w + x]; count++; }
    return { map: map, mean: sum / count };
  }
  // LDR-FLIP of A (test) against B (reference) over the displayed sRGB, the passes of
  // shaders/metrics/flip.wgsl (a tap-by-tap port of flip-rs) with flip-rs's filters from the run
  // (compare::gpu::flip_filters), in double precision where flip-rs computes in f32.
  function clamp01(v) { return v > 0 ? Math.min(v, 1) : 0; }
  function toXyz(r, g, b) {
    return [
      (10135552 / 24577794) * r + (8788810 / 24577794) * g + (4435075 / 24577794) * b,
      (2613072 / 12288897) * r + (8788810 / 12288897) * g + (887015 / 12288897) * b,
      (1425312 / 73733382) * r + (8788810 / 73733382) * g + (70074185 / 73733382) * b
    ];
  }
  function labF(v) {
    var d = 6 / 29;
    return v > d * d * d ? Math.pow(v, 1 / 3) : (1 / (3 * d * d)) * v + 4 / 29;
  }
  function filteredLab(yp, cx, cz) {
    var y = (yp + 16) / 116, x = (y + cx / 500) * 0.950428545, z = (y - cz / 200) * 1.088900371;
    var xyz = toXyz(
      clamp01(3.241003275 * x + -1.537398934 * y + -0.498615861 * z),
      clamp01(-0.969224334 * x + 1.875930071 * y + 0.041554224 * z),
      clamp01(0.055639423 * x + -0.204011202 * y + 1.057148933 * z));
    var fx = labF(xyz[0] * 1.052156925), fy = labF(xyz[1]), fz = labF(xyz[2] * 0.918357670), l = 116 * fy - 16;
    return [l, 0.01 * l * (500 * (fx - fy)), 0.01 * l * (200 * (fy - fz))];
  }
  function flip(T, R) {
    var F = D.flip, w = R.width, h = R.height, n = R.n;
    if (T.width !== w || T.height !== h) return { why: 'A and B differ in size' };
    var rs = (F.spatial.length - 1) / 2, rf = (F.feature.length - 1) / 2, i, x, y, k, c;
    var clampTo = function (v, size) { return v < 0 ? 0 : (v >= size ? size - 1 : v); };
    var opponent = [R, T].map(function (P) {
      var o = new Float64Array(3 * n), lin = function (v) { v = clamp01(v / 255); return v <= 0.04045 ? v / 12.92 : Math.pow((v + 0.055) / 1.055, 2.4); };
      for (var p = 0; p < n; p++) {
        var xyz = toXyz(lin(P.srgb[p]), lin(P.srgb[n + p]), lin(P.srgb[2 * n + p]));
        var X = xyz[0] * 1.052156925, Y = xyz[1], Z = xyz[2] * 0.918357670;
        o[p] = 116 * Y - 16; o[n + p] = 500 * (X - Y); o[2 * n + p] = 200 * (Y - Z);
      }
      return o;
    });
    // Colour: the CSF filters, rows then columns, then HyAB^0.7 of the filtered Lab.
    var inter = [];
    for (c = 0; c < 8; c++) {
      var src = opponent[c >> 2], plane = Math.min(c % 4, 2), out = new Float64Array(n);
      for (i = 0; i < n; i++) {
        x = i % w; var row = i - x, sum = 0;
        for (k = -rs; k <= rs; k++) sum += F.spatial[k + rs][c % 4] * src[plane * n + row + clampTo(x + k, w)];
        out[i] = sum;
      }
      inter.push(out);
    }
    var cmax = F.cmax, knee = 0.4 * cmax, colour = new Float64Array(n), s = new Float64Array(8);
    for (i = 0; i < n; i++) {
      x = i % w; y = (i - x) / w; s.fill(0);
      for (k = -rs; k <= rs; k++) {
        var wt = F.spatial[k + rs], j = clampTo(y + k, h) * w + x;
        for (c = 0; c < 8; c++) s[c] += wt[c % 4] * inter[c][j];
      }
      var lr = filteredLab(s[0], s[1], s[2] + s[3]), lt = filteredLab(s[4], s[5], s[6] + s[7]);
      var da = lr[1] - lt[1], db = lr[2] - lt[2];
      var d = Math.pow(Math.abs(lr[0] - lt[0]) + Math.sqrt(da * da + db * db), 0.7);
      colour[i] = d < knee ? d * (0.95 / knee) : 0.95 + ((d - knee) / (cmax - knee)) * (1 - 0.95);
    }
    // Features: edges and points of the normalised luminance, rows then columns.
    var feat = [0, 1].map(function (image) {
      var dg = new Float64Array(n), ddg = new Float64Array(n), g = new Float64Array(n), o = opponent[image];
      for (var q = 0; q < n; q++) {
        var qx = q % w, qrow = q - qx, a = 0, b = 0, e = 0;
        for (var t = -rf; t <= rf; t++) {
          var f = F.feature[t + rf], v = o[qrow + clampTo(qx + t, w)] * (1 / 116) + 16 / 116;
          a += f[1] * v; b += f[2] * v; e += f[0] * v;
        }
        dg[q] = a; ddg[q] = b; g[q] = e;
      }
      return [dg, ddg, g];
    });
    var map = new Float64Array(n), total = 0;
    for (i = 0; i < n; i++) {
      x = i % w; y = (i - x) / w; s.fill(0);
      for (k = -rf; k <= rf; k++) {
        var fw = F.feature[k + rf], jj = clampTo(y + k, h) * w + x;
        for (var im = 0; im < 2; im++) {
          s[im * 4] += fw[0] * feat[im][0][jj];
          s[im * 4 + 1] += fw[0] * feat[im][1][jj];
          s[im * 4 + 2] += fw[1] * feat[im][2][jj];
          s[im * 4 + 3] += fw[2] * feat[im][2][jj];
        }
      }
      var edge = Math.abs(Math.sqrt(s[0] * s[0] + s[2] * s[2]) - Math.sqrt(s[4] * s[4] + s[6] * s[6]));
      var point = Math.abs(Math.sqrt(s[1] * s[1] + s[3] * s[3]) - Math.sqrt(s[5] * s[5] + s[7] * s[7]));
      var exponent = 1 - Math.sqrt((1 / Math.sqrt(2)) * Math.max(edge, point));
      map[i] = exponent !== 0 ? Math.pow(colour[i], exponent) : 1;
      total += map[i];
    }
    return { map: map, mean: total / n };
  }

  // A heat colour for t in [0, 1] (black → red → yellow).
  function heat(data, p, t) {
    data[4 * p] = 255 * Math.min(1, 2 * t); data[4 * p + 1] = 255 * Math.max(0, 2 * t - 1);
    data[4 * p + 2] = 64 * (1 - t); data[4 * p + 3] = 255;
  }

  // ---- the view ----
  // bref: B shows A's own reference rather than a cell.
  var current = { a: null, b: null, bref: false };
  function img(src, cls) {
    var im = document.createElement('img');
    im.src = src; im.alt = src; im.decoding = 'async';
    if (cls) im.className = cls;
    return im;
  }
  function overlayFor(i, other, ref) {
    if (state.overlay === 'none' || i === null) return null;
    var c = cells[i], w = c[8][0] * state.zoom, h = c[8][1] * state.zoom;
    if (state.overlay === 'noise') {
      // The truth's noise belongs to the reference: over A and over its reference alike.
      if ((c[7] & 16) === 0) { $('pair').textContent = 'A\'s reference is not a truth: it has no noise map'; return null; }
      var nz = img(cellDir(i) + '/truth_noise.png', 'over');
      nz.style.width = w + 'px'; nz.style.height = h + 'px'; nz.style.opacity = state.opacity;
      $('pair').textContent = 'noise of the truth: each pixel\'s standard error over its luminance, full colour at 20 %';
      return nz;
    }
    // A reference has no map against itself, and its pixel values are not in the page.
    if (ref) return null;
    if (state.overlay === 'diff' || state.overlay === 'ssim_ab' || state.overlay === 'flip_ab') {
      if (other === null || current.bref) return null;
      var cv = document.createElement('canvas');
      cv.width = c[8][0]; cv.height = c[8][1]; cv.className = 'over';
      cv.style.width = w + 'px'; cv.style.height = h + 'px'; cv.style.opacity = state.opacity;
      cv.style.imageRendering = 'pixelated';
      Promise.all([loadPixels(i), loadPixels(other)]).then(function (pp) {
        var A = pp[0], B = pp[1];
        if (!A || !B || A.n !== B.n) return;
        var ctx = cv.getContext('2d'), im = ctx.createImageData(A.width, A.height), p;
        var note = $('pair');
        if (state.overlay === 'flip_ab') {
          var fl = flip(A, B);
          if (!fl.map) { note.textContent = 'FLIP of A against B: ' + fl.why; return; }
          for (p = 0; p < A.n; p++) heat(im.data, p, Math.min(1, Math.max(0, fl.map[p])));
          note.textContent = 'LDR-FLIP of A against B (computed here, the passes of flip-rs): ' + fl.mean.toFixed(6);
          note.dataset.flip = fl.mean;
        } else if (state.overlay === 'ssim_ab') {
          var r = ssim(A, B);
          if (!r.map) { note.textContent = 'SSIM of A against B: ' + r.why; return; }
          for (p = 0; p < A.n; p++) heat(im.data, p, Math.min(1, Math.max(0, 1 - r.map[p])));
          note.textContent = 'SSIM of A against B (computed here, as compare::ssim): ' + r.mean.toFixed(6);
          note.dataset.ssim = r.mean;
        } else {
          for (p = 0; p < A.n; p++) {
            var d = 0;
            for (var ch = 0; ch < 3; ch++) d = Math.max(d, Math.abs(A.srgb[ch * A.n + p] - B.srgb[ch * B.n + p]));
            heat(im.data, p, Math.min(1, d / 64));
          }
          note.textContent = '|A − B| of the displayed sRGB, full colour at a difference of 64';
        }
        ctx.putImageData(im, 0, 0);
      });
      return cv;
    }
    if ((c[7] & 1) === 0) return null;
    var o = img(cellDir(i) + '/' + state.overlay + '.png', 'over');
    o.style.width = w + 'px'; o.style.height = h + 'px'; o.style.opacity = state.opacity;
    return o;
  }
  function stage(i, other, ref) {
    var s = document.createElement('div');
    s.className = 'stage';
    if (i === null) return s;
    var c = cells[i], base = img(picture(i, ref));
    base.style.width = c[8][0] * state.zoom + 'px'; base.style.height = c[8][1] * state.zoom + 'px';
    s.appendChild(base);
    var o = overlayFor(i, other, ref);
    if (o) s.appendChild(o);
    track(s, c);
    return s;
  }
  function track(el, c) {
    el.addEventListener('mousemove', function (e) {
      var r = el.getBoundingClientRect();
      var x = Math.floor((e.clientX - r.left) / state.zoom), y = Math.floor((e.clientY - r.top) / state.zoom);
      if (x < 0 || y < 0 || x >= c[8][0] || y >= c[8][1]) return;
      state.px = [x, y]; writeHash(); readout();
    });
  }
  function pane(label, i, other, why, ref) {
    var p = document.createElement('div'); p.className = 'pane';
    var h = document.createElement('h3'); h.textContent = label; p.appendChild(h);
    p.appendChild(stage(i, other, ref));
    var id = document.createElement('div'); id.className = 'id';
    id.textContent = i === null ? why : (ref ? referenceName(i) : cells[i][0]);
    p.appendChild(id);
    return p;
  }
  function referenceName(i) { return cells[i][0] + ': its own reference (' + (cells[i][9] || 'reference') + ')'; }
  function wipeStage(a, b) {
    var s = stage(a, b);
    if (a === null || b === null) return s;
    var c = cells[b], top = img(picture(b, current.bref), 'b-clip');
    top.style.width = c[8][0] * state.zoom + 'px'; top.style.height = c[8][1] * state.zoom + 'px';
    top.style.clipPath = 'inset(0 0 0 ' + (state.wipe * 100).toFixed(2) + '%)';
    top.id = 'wipe-b';
    s.appendChild(top);
    var div = document.createElement('div'); div.id = 'divider';
    div.style.left = 'calc(' + (state.wipe * 100).toFixed(2) + '% - 1px)';
    s.appendChild(div);
    var drag = false;
    div.addEventListener('pointerdown', function (e) { drag = true; div.setPointerCapture(e.pointerId); });
    div.addEventListener('pointerup', function () { drag = false; writeHash(); });
    div.addEventListener('pointermove', function (e) {
      if (!drag) return;
      var r = s.getBoundingClientRect();
      state.wipe = Math.min(1, Math.max(0, (e.clientX - r.left) / r.width));
      top.style.clipPath = 'inset(0 0 0 ' + (state.wipe * 100).toFixed(2) + '%)';
      div.style.left = 'calc(' + (state.wipe * 100).toFixed(2) + '% - 1px)';
    });
    return s;
  }

  function metricsText(i) {
    var c = cells[i], m = c[4], f = function (v) { return v === null ? '—' : v.toFixed(4); };
    var ref = c[3] >= 0 ? cells[c[3]][0] : (c[9] || 'none');
    return 'against ' + ref + ': FLIP ' + f(m[0]) + ' · SSIM ' + f(m[1]) + ' · HDR-FLIP ' + f(m[2]);
  }
  function recordText(label, i, why, ref) {
    if (i === null) return label + ': ' + why;
    if (ref) return label + ': ' + referenceName(i) + ' (reference.png; its linear values: reference.exr)';
    var c = cells[i], lines = [label + ': ' + c[0]];
    shown.forEach(function (k) { lines.push('  ' + axes[k].name + ' = ' + axes[k].values[c[1][k]]); });
    if (c[2] >= 0) lines.push('  twin of ' + cells[c[2]][0] + ' (the shader ignores the axes they differ in; images copied)');
    lines.push('  ' + metricsText(i));
    var t = c[10], ms = function (v) { return v === null ? '—' : v.toFixed(3) + ' ms'; };
    lines.push('  GPU median ' + ms(c[5]) + ' · CPU wall median ' + ms(t[0]) + ' · ' + c[8][0] + '×' + c[8][1]);
    if (t[2].length) lines.push('  GPU per pass: ' + t[2].map(function (p) { return D.pass_kinds[p[0]] + ' ' + p[1].toFixed(3); }).join(', ') + ' ms');
    if (t[1] >= 0) lines.push('  timings of ' + cells[t[1]][0] + ' (same timing class; this cell rendered one untimed frame)');
    lines.push('  passes: ' + D.plans[c[6]].join(' → '));
    return lines.join('\n');
  }

  // One decoded image per cell for the magnifier: a mouse move redraws, it does not reload.
  var magnifiedImages = new Map();
  function magnified(i, ref) {
    var src = picture(i, ref);
    if (!magnifiedImages.has(src)) { var im = new Image(); im.src = src; magnifiedImages.set(src, im); }
    return magnifiedImages.get(src);
  }
  function readout() {
    var out = $('readout');
    if (!state.px) { out.textContent = 'hover the image to read a pixel'; return; }
    var x = state.px[0], y = state.px[1];
    ['a', 'b'].forEach(function (side) {
      var i = current[side], cv = $('mag-' + side), ctx = cv.getContext('2d');
      ctx.imageSmoothingEnabled = false;
      ctx.fillStyle = '#000'; ctx.fillRect(0, 0, cv.width, cv.height);
      if (i === null) return;
      var im = magnified(i, side === 'b' && current.bref), draw = function () {
        ctx.drawImage(im, x - 5, y - 5, 11, 11, 0, 0, 165, 165);
        ctx.strokeStyle = '#ffcc33'; ctx.strokeRect(75, 75, 15, 15);
      };
      if (im.complete && im.naturalWidth) draw(); else im.addEventListener('load', draw, { once: true });
    });
    var token = (readout.token = (readout.token || 0) + 1);
    var bPixels = current.b === null || current.bref ? null : loadPixels(current.b);
    Promise.all([current.a === null ? null : loadPixels(current.a), bPixels])
      .then(function (pp) {
        if (token !== readout.token) return;
        var lines = ['pixel ' + x + ', ' + y];
        ['a', 'b'].forEach(function (side, n) {
          if (current[side] === null) { lines.push(side.toUpperCase() + ': no cell'); return; }
          if (side === 'b' && current.bref) { lines.push('B: the reference (its values: reference.exr; the magnifier shows it)'); return; }
          var t = pixelText(pp[n], x, y);
          if (typeof t === 'string') { lines.push(side.toUpperCase() + ': ' + t); return; }
          out.dataset[side + 'Srgb'] = t.srgb.join(',');
          out.dataset[side + 'Linear'] = t.linear.join(',');
          lines.push(side.toUpperCase() + ': ' + t.text);
        });
        out.dataset.px = x + ',' + y;
        out.textContent = lines.join('\n');
      });
  }

  // ---- state ⇄ URL fragment ----
  function encodeState() {
    var parts = [];
    shown.forEach(function (k) {
      parts.push('a.' + axes[k].name + '=' + encodeURIComponent(axes[k].values[state.a[k]]));
      parts.push('b.' + axes[k].name + '=' + encodeURIComponent(axes[k].values[state.b[k]]));
    });
    parts.push('link=' + (state.link ? 1 : 0), 'bref=' + (state.bref ? 1 : 0), 'mode=' + state.mode, 'overlay=' + state.overlay,
      'term=' + encodeURIComponent(state.term), 'opacity=' + state.opacity, 'zoom=' + state.zoom, 'wipe=' + state.wipe.toFixed(3), 'flicker=' + (state.flickerB ? 'b' : 'a'));
    if (state.px) parts.push('px=' + state.px.join(','));
    return parts.join('&');
  }
  // Applies the fragment; returns, per side, the axes it named (the ones a snap keeps).
  function applyHash(hash) {
    var named = { a: [], b: [] };
    hash.replace(/^#/, '').split('&').forEach(function (kv) {
      var eq = kv.indexOf('=');
      if (eq < 0) return;
      var key = kv.slice(0, eq), val = decodeURIComponent(kv.slice(eq + 1));
      var m = /^([ab])\.(.+)$/.exec(key);
      if (m && AXIS[m[2]] !== undefined) {
        var k = AXIS[m[2]], vi = axes[k].values.indexOf(val);
        if (vi >= 0) { state[m[1]][k] = vi; named[m[1]].push(k); }
      } else if (key === 'link') state.link = val === '1';
      else if (key === 'bref') state.bref = val === '1';
      else if (key === 'mode' && /^(side|wipe|flicker)$/.test(val)) state.mode = val;
      else if (key === 'overlay' && /^(none|flip|ssim|flip_ab|ssim_ab|diff|noise)$/.test(val)) state.overlay = val;
      else if (key === 'term' && (val === 'image' || (D.terms || []).indexOf(val) >= 0)) state.term = val;
      else if (key === 'opacity') state.opacity = Math.min(1, Math.max(0, +val || 0));
      else if (key === 'zoom') state.zoom = Math.min(8, Math.max(1, Math.round(+val) || 2));
      else if (key === 'wipe') state.wipe = Math.min(1, Math.max(0, +val || 0));
      else if (key === 'flicker') state.flickerB = val === 'b';
      else if (key === 'px') { var xy = val.split(',').map(Number); if (xy.length === 2 && xy.every(isFinite)) state.px = xy; }
    });
    return named;
  }
  function applyHashAndSnap(hash) {
    var named = applyHash(hash);
    snap('a', named.a); snap('b', named.b);
  }
  var lastHash = '';
  function writeHash() {
    lastHash = '#' + encodeState();
    if (location.hash !== lastHash) history.replaceState(null, '', lastHash);
  }
  window.addEventListener('hashchange', function () {
    if (location.hash === lastHash) return;
    applyHashAndSnap(location.hash); update();
  });

  function update() {
    shown.forEach(function (k) {
      ['a', 'b'].forEach(function (side) {
        var ctl = controls[side][k];
        ctl.el.value = state[side][k];
        if (ctl.out) ctl.out.textContent = axes[k].values[state[side][k]];
        ctl.el.disabled = side === 'b' && (state.bref || (state.link && axes[k].kind !== 'choice'));
      });
    });
    $('link').checked = state.link;
    $('bref').checked = state.bref;
    $('overlay').value = state.overlay;
    $('term').value = state.term;
    $('opacity').value = state.opacity; $('opacity-value').textContent = state.opacity;
    $('zoom').value = state.zoom; $('zoom-value').textContent = state.zoom + '×';
    ['side', 'wipe', 'flicker'].forEach(function (m) { $('mode-' + m).classList.toggle('on', state.mode === m); });
    var ra = resolve(state.a), rb = resolve(state.b);
    current.a = ra.cell === undefined ? null : ra.cell;
    current.b = rb.cell === undefined ? null : rb.cell;
    current.bref = false;
    if (state.bref) {
      // B: A's own reference, where A has one (a truth or a supersampled render of its own).
      var own = current.a !== null && (cells[current.a][7] & 8) !== 0;
      current.b = own ? current.a : null;
      current.bref = own;
      rb = { why: current.a === null ? 'no cell A' : 'A has no reference image of its own (it is compared with ' + (cells[current.a][3] >= 0 ? cells[cells[current.a][3]][0] : 'nothing') + ')' };
    }
    $('why-a').textContent = current.a === null ? 'A: ' + ra.why : '';
    $('why-b').textContent = current.b === null ? 'B: ' + rb.why : '';
    var wrap = $('stage-wrap');
    wrap.innerHTML = '';
    $('pair').textContent = ''; delete $('pair').dataset.ssim; delete $('pair').dataset.flip;
    if (state.mode === 'side') {
      wrap.appendChild(pane('A', current.a, current.b, ra.why));
      wrap.appendChild(pane(current.bref ? 'B: A\'s reference' : 'B', current.b, current.a, rb.why, current.bref));
    } else if (state.mode === 'wipe') {
      var w = pane('A | B (drag the divider)', current.a, current.b, ra.why);
      w.replaceChild(wipeStage(current.a, current.b), w.querySelector('.stage'));
      wrap.appendChild(w);
    } else {
      var showB = state.flickerB;
      var i = showB ? current.b : current.a;
      wrap.appendChild(pane((showB ? (current.bref ? 'B: A\'s reference' : 'B') : 'A') + ' (F flips)', i,
        showB ? current.a : current.b, showB ? rb.why : ra.why, showB && current.bref));
    }
    $('record').textContent = recordText('A', current.a, ra.why) + '\n\n' + recordText('B', current.b, rb.why, current.bref);
    wrap.dataset.a = current.a === null ? '' : cells[current.a][0];
    wrap.dataset.b = current.b === null ? '' : (current.bref ? 'reference:' : '') + cells[current.b][0];
    writeHash();
    readout();
  }

  var r = D.run;
  $('summary').textContent = r.name + ' · ' + r.cells + ' cells (' + r.rendered + ' rendered, ' + r.twins +
    ' twins, ' + r.pruned + ' pruned) · ' + r.adapter + ' · ' + r.status + ' · matrix ' + r.matrix;
  D.links.forEach(function (l) {
    var a = document.createElement('a'); a.href = l[1]; a.textContent = l[0]; $('links').appendChild(a);
  });
  applyHashAndSnap(location.hash);
  update();
  document.body.dataset.ready = '1';
  document.body.dataset.loadMs = performance.now().toFixed(1);
})();
