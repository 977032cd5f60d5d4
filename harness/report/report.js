// vshadow report: draws the page from the JSON in script#report-data (harness/report/report.cpp).
// Plain JavaScript, no libraries, no network. Every value is shown as its text in the CSV.
// URL hash #selftest runs the page's own checks and writes a JSON verdict into pre#selftest.
(function () {
  'use strict';

  // Problems the self-test reports: script errors, failed image loads, console.error calls.
  var problems = [];
  window.addEventListener('error', function (e) {
    var t = e.target;
    if (t && t !== window && (t.src || t.currentSrc)) problems.push('cannot load ' + (t.currentSrc || t.src));
    else problems.push('error: ' + (e.message || e) + (e.filename ? ' at ' + e.filename + ':' + e.lineno : ''));
  }, true);
  window.addEventListener('unhandledrejection', function (e) { problems.push('unhandled rejection: ' + e.reason); });
  var consoleError = console.error;
  console.error = function () {
    problems.push('console.error: ' + Array.prototype.join.call(arguments, ' '));
    consoleError.apply(console, arguments);
  };

  var started = performance.now();
  var data = JSON.parse(document.getElementById('report-data').textContent);
  var PAGE_SIZE = 50;
  var PALETTE = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf', '#8c564b', '#e377c2',
                 '#bcbd22', '#7f7f7f', '#393b79', '#637939'];
  var PASS_OWN = ['#2563eb', '#f97316', '#16a34a', '#9333ea', '#dc2626', '#0891b2', '#ca8a04', '#db2777',
                  '#4f46e5', '#65a30d'];
  var PASS_SHARED = ['#9ca3af', '#cbd5e1', '#6b7280', '#d1d5db', '#94a3b8', '#e5e7eb'];
  var METRICS = ['ls_rmse', 'ls_relmse', 'rmse', 'relmse', 'exact_ls_relmse', 'exact_ls_rmse', 'seq_ls_rmse_mean'];
  // Columns the table shows by default (when the scene has values in them); [column, min, max] shows a range.
  var DEFAULT_COLUMNS = [
    ['method'], ['series'], ['params'], ['status'], ['scatter_ms', 'scatter_round_min_ms', 'scatter_round_max_ms'],
    ['frame_median_ms', 'frame_round_min_ms', 'frame_round_max_ms'], ['frame_p99_ms'], ['ls_rmse'], ['ls_relmse'],
    ['rmse'], ['psnr'], ['ssim'], ['exact_ls_relmse'], ['eq_error_against'], ['eq_uniform_steps'],
    ['eq_uniform_ms', 'eq_uniform_round_min_ms', 'eq_uniform_round_max_ms'],
    ['speedup_eq_uniform', 'speedup_eq_uniform_round_min', 'speedup_eq_uniform_round_max'],
    ['equal_time_ls_rmse_uniform'], ['eq_equiangular_steps'],
    ['eq_equiangular_ms', 'eq_equiangular_round_min_ms', 'eq_equiangular_round_max_ms'],
    ['speedup_eq_equiangular', 'speedup_eq_equiangular_round_min', 'speedup_eq_equiangular_round_max'],
    ['equal_time_ls_rmse_equiangular'], ['seq_ls_rmse_mean'], ['seq_ls_rmse_max'], ['temporal_ls_rel'],
    ['frame_mdape_pct'], ['disturbed'], ['width'], ['height'], ['seed'], ['host'], ['shard'], ['reason']];

  // ---- helpers
  function esc(s) {
    return String(s).replace(/[&<>"']/g, function (c) {
      return { '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' }[c];
    });
  }
  function el(tag, attrs, html) {
    var e = document.createElement(tag);
    for (var k in attrs || {}) {
      if (k === 'text') e.textContent = attrs[k];
      else if (k === 'cls') e.className = attrs[k];
      else e.setAttribute(k, attrs[k]);
    }
    if (html !== undefined) e.innerHTML = html;
    return e;
  }
  // The number in a CSV field ('>=' marks a lower bound), NaN when there is none.
  function num(s) {
    if (s === undefined || s === null) return NaN;
    s = String(s).trim();
    if (s.slice(0, 2) === '>=') s = s.slice(2);
    if (s === '' || !/^[-+]?(\d|\.\d|inf)/i.test(s)) return NaN;
    if (/^[-+]?inf/i.test(s)) return s[0] === '-' ? -Infinity : Infinity;
    return Number(s);
  }
  function positive(v) { return isFinite(v) && v > 0; }
  function tickLabel(v) {
    if (v >= 1e5 || v < 1e-3) return v.toExponential(0).replace('e+', 'e');
    return String(Number(v.toPrecision(3)));
  }
  var tooltip = document.getElementById('tooltip');
  function showTip(ev, text) {
    tooltip.textContent = text;
    tooltip.hidden = false;
    var x = ev.clientX + 14, y = ev.clientY + 14;
    if (x + 470 > window.innerWidth) x = Math.max(4, ev.clientX - 470);
    tooltip.style.left = x + 'px';
    tooltip.style.top = y + 'px';
  }
  function hideTip() { tooltip.hidden = true; }

  // ---- the scene's model: rows as arrays, columns by name
  function Scene(raw, index) {
    var s = this;
    s.raw = raw;
    s.index = index;
    s.id = 'scene-' + index;
    s.col = {};
    raw.columns.forEach(function (c, i) { s.col[c] = i; });
    s.rows = raw.rows;
    s.selected = -1;
    s.methodKeys = [];
    s.rows.forEach(function (r, i) {
      var k = s.methodKey(i);
      if (s.methodKeys.indexOf(k) < 0) s.methodKeys.push(k);
    });
    s.metric = METRICS.filter(function (m) { return s.hasValues(m, true); })[0] || null;
  }
  Scene.prototype.get = function (row, column) {
    var i = this.col[column];
    return i === undefined ? '' : this.rows[row][i];
  };
  Scene.prototype.hasValues = function (column, positiveOnly) {
    var i = this.col[column];
    if (i === undefined) return false;
    return this.rows.some(function (r) { return positiveOnly ? positive(num(r[i])) : r[i] !== ''; });
  };
  Scene.prototype.methodKey = function (row) {
    var series = this.get(row, 'series');
    return this.get(row, 'method') + (series ? ' (' + series + ')' : '');
  };
  Scene.prototype.colour = function (row) {
    return PALETTE[this.methodKeys.indexOf(this.methodKey(row)) % PALETTE.length];
  };
  // Success rows with a positive time and error: what the chart draws.
  Scene.prototype.plottable = function (timeColumn, metric) {
    var out = [];
    for (var i = 0; i < this.rows.length; ++i) {
      if (this.get(i, 'status') !== 'Success') continue;
      var t = num(this.get(i, timeColumn)), e = num(this.get(i, metric));
      if (positive(t) && positive(e)) out.push({ row: i, x: t, y: e });
    }
    return out;
  };
  Scene.prototype.describe = function (row) {
    var s = this, lines = [s.methodKey(row), 'params: ' + s.get(row, 'params')];
    if (s.get(row, 'status') !== 'Success') lines.push(s.get(row, 'status') + ': ' + s.get(row, 'reason'));
    ['ls_rmse', 'ls_relmse', 'rmse', 'exact_ls_relmse', 'scatter_ms', 'frame_median_ms'].forEach(function (c) {
      if (s.get(row, c) !== '') lines.push(c + ': ' + s.get(row, c) + range(s, row, c));
    });
    [['speedup_eq_uniform', 'uniform'], ['speedup_eq_equiangular', 'equiangular']].forEach(function (p) {
      if (s.get(row, p[0]) !== '')
        lines.push('speed-up at equal L_s error over ' + p[1] + ' ray marching: ' + s.get(row, p[0]) + 'x' +
                   range(s, row, p[0]) + ' (' + s.get(row, p[0].replace('speedup_', '') + '_steps') + ' steps)');
    });
    if (s.get(row, 'disturbed') === '1') lines.push('disturbed: timed while the machine\'s speed moved');
    return lines.join('\n');
  };
  function rangeColumns(column) {
    if (/_ms$/.test(column) && column !== 'setup_ms') {
      var base = column.replace(/_median_ms$|_ms$/, '');
      return [base + '_round_min_ms', base + '_round_max_ms'];
    }
    if (/^speedup_/.test(column)) return [column + '_round_min', column + '_round_max'];
    return null;
  }
  function range(scene, row, column) {
    var rc = rangeColumns(column);
    if (!rc) return '';
    var lo = scene.get(row, rc[0]), hi = scene.get(row, rc[1]);
    return lo !== '' && hi !== '' && (lo !== hi || num(scene.get(row, 'rounds')) > 1) ? ' [' + lo + '\u2013' + hi + ']' : '';
  }

  // ---- SVG charts
  function Axis(lo, hi, log, from, to) {
    if (log) { lo = Math.log10(lo); hi = Math.log10(hi); }
    if (!(hi > lo)) { lo -= log ? 0.5 : Math.abs(lo) * 0.5 + 1; hi += log ? 0.5 : Math.abs(hi) * 0.5 + 1; }
    var pad = (hi - lo) * 0.06;
    this.lo = lo - pad; this.hi = hi + pad; this.log = log; this.from = from; this.to = to;
  }
  Axis.prototype.map = function (v) {
    var t = ((this.log ? Math.log10(v) : v) - this.lo) / (this.hi - this.lo);
    return this.from + t * (this.to - this.from);
  };
  Axis.prototype.ticks = function () {
    var out = [], k;
    if (this.log) {
      // Decades, else 1-2-5 steps, else every integer multiple: whichever first gives three ticks.
      var sets = [[1], [1, 2, 5], [1, 2, 3, 4, 5, 6, 7, 8, 9]], inside = [];
      for (var n = 0; n < sets.length && inside.length < 3; ++n) {
        out = [];
        for (k = Math.floor(this.lo); k <= Math.ceil(this.hi); ++k)
          sets[n].forEach(function (m) { out.push(m * Math.pow(10, k)); });
        inside = out.filter(function (v) { return this.inside(v); }, this);
      }
      return inside;
    }
    var step = Math.pow(10, Math.floor(Math.log10((this.hi - this.lo) / 4)));
    [1, 2, 5, 10].some(function (m) { if ((this.hi - this.lo) / (step * m) <= 6) { step *= m; return true; } }, this);
    for (k = Math.ceil(this.lo / step); k * step <= this.hi; ++k) out.push(k * step);
    return out;
  };
  Axis.prototype.inside = function (v) {
    var x = this.log ? Math.log10(v) : v;
    return x >= this.lo && x <= this.hi;
  };
  // A chart frame: axes, grid, labels; returns the SVG's opening, the axes and its closing text.
  function frame(w, h, xs, ys, xLog, yLog, xLabel, yLabel, title) {
    var L = 58, R = 12, T = 22, B = 40;
    var ax = new Axis(Math.min.apply(null, xs), Math.max.apply(null, xs), xLog, L, w - R);
    var ay = new Axis(Math.min.apply(null, ys), Math.max.apply(null, ys), yLog, h - B, T);
    var s = '<svg class="chart" xmlns="http://www.w3.org/2000/svg" width="' + w + '" height="' + h + '" viewBox="0 0 ' +
            w + ' ' + h + '">';
    s += '<text x="' + L + '" y="14" font-weight="600">' + esc(title) + '</text>';
    ax.ticks().forEach(function (v) {
      var x = ax.map(v).toFixed(1);
      s += '<line class="grid" x1="' + x + '" x2="' + x + '" y1="' + T + '" y2="' + (h - B) + '"/>';
      s += '<text x="' + x + '" y="' + (h - B + 14) + '" text-anchor="middle">' + tickLabel(v) + '</text>';
    });
    ay.ticks().forEach(function (v) {
      var y = ay.map(v).toFixed(1);
      s += '<line class="grid" x1="' + L + '" x2="' + (w - R) + '" y1="' + y + '" y2="' + y + '"/>';
      s += '<text x="' + (L - 4) + '" y="' + y + '" dy="4" text-anchor="end">' + tickLabel(v) + '</text>';
    });
    s += '<rect class="axis" fill="none" x="' + L + '" y="' + T + '" width="' + (w - L - R) + '" height="' + (h - T - B) + '"/>';
    s += '<text x="' + ((L + w - R) / 2) + '" y="' + (h - 6) + '" text-anchor="middle">' + esc(xLabel) + '</text>';
    s += '<text transform="translate(12,' + ((T + h - B) / 2) + ') rotate(-90)" text-anchor="middle">' + esc(yLabel) + '</text>';
    return { head: s, ax: ax, ay: ay, tail: '</svg>' };
  }
  // Points that no other point beats on both time and error (as scripts/plot), by time.
  function paretoFront(points) {
    var sorted = points.slice().sort(function (a, b) { return a.x - b.x || a.y - b.y; });
    var front = [], best = Infinity;
    sorted.forEach(function (p) { if (p.y < best) { front.push(p); best = p.y; } });
    return front;
  }
  var TIME_LABELS = { scatter_ms: 'scattering time, median (ms)', frame_median_ms: 'frame time, median (ms)' };
  function errorChart(scene, timeColumn) {
    var metric = scene.metric, pts = scene.plottable(timeColumn, metric);
    if (!pts.length) return '<p class="muted">No Success row has a positive ' + esc(timeColumn) + ' and ' + esc(metric) + '.</p>';
    var f = frame(470, 340, pts.map(function (p) { return p.x; }), pts.map(function (p) { return p.y; }), true, true,
                  TIME_LABELS[timeColumn] + ', log', metric + ' (lower is better), log', scene.raw.name + ': ' + metric +
                  ' against ' + (timeColumn === 'scatter_ms' ? 'scattering' : 'frame') + ' time');
    var s = f.head, byMethod = {};
    pts.forEach(function (p) { (byMethod[scene.methodKey(p.row)] = byMethod[scene.methodKey(p.row)] || []).push(p); });
    Object.keys(byMethod).forEach(function (k) {
      var line = byMethod[k].slice().sort(function (a, b) { return a.x - b.x; });
      if (line.length < 2 || line.length > 400) return;
      s += '<polyline fill="none" stroke-width="1" stroke-opacity="0.6" stroke="' + scene.colour(line[0].row) + '" points="' +
           line.map(function (p) { return f.ax.map(p.x).toFixed(1) + ',' + f.ay.map(p.y).toFixed(1); }).join(' ') + '"/>';
    });
    var front = paretoFront(pts), step = '';
    front.forEach(function (p, i) {
      var x = f.ax.map(p.x).toFixed(1), y = f.ay.map(p.y).toFixed(1);
      step += (i ? ' H' + x + ' V' + y : 'M' + x + ',' + y);
    });
    s += '<path class="frontline" d="' + step + '"/>';
    front.forEach(function (p) {
      s += '<circle class="front" r="6.5" cx="' + f.ax.map(p.x).toFixed(1) + '" cy="' + f.ay.map(p.y).toFixed(1) + '"/>';
    });
    var onFront = {};
    front.forEach(function (p) { onFront[p.row] = true; });
    pts.forEach(function (p) {
      s += '<circle class="pt' + (p.row === scene.selected ? ' sel' : '') + '" data-row="' + p.row + '"' +
           (onFront[p.row] ? ' data-front="1"' : '') + ' r="3.6" cx="' + f.ax.map(p.x).toFixed(1) + '" cy="' +
           f.ay.map(p.y).toFixed(1) + '" fill="' + scene.colour(p.row) + '"/>';
    });
    return s + f.tail;
  }
  function lineChart(title, xLabel, yLabel, yLog, lines) {
    var xs = [], ys = [];
    lines.forEach(function (l) { l.pts.forEach(function (p) { xs.push(p[0]); ys.push(p[1]); }); });
    if (!xs.length) return '';
    var f = frame(470, 280, xs, ys, false, yLog, xLabel, yLabel, title), s = f.head;
    lines.forEach(function (l) {
      s += '<polyline data-row="' + l.row + '" fill="none" stroke-width="1.5" stroke="' + l.colour + '" points="' +
           l.pts.map(function (p) { return f.ax.map(p[0]).toFixed(1) + ',' + f.ay.map(p[1]).toFixed(1); }).join(' ') +
           '"><title>' + esc(l.label) + '</title></polyline>';
    });
    return s + f.tail;
  }

  // ---- the rows table: sorted, filtered, paginated
  function Table(scene, host) {
    this.scene = scene;
    this.host = host;
    this.sortColumn = null;
    this.sortDir = 1;
    this.filter = '';
    this.status = '';
    this.page = 0;
    this.all = false;
    this.order = scene.rows.map(function (r, i) { return i; });
    this.view = this.order;
  }
  Table.prototype.columns = function () {
    var scene = this.scene;
    if (this.all) return scene.raw.columns.map(function (c) { return [c]; }).concat([['(passes)']]);
    var cols = DEFAULT_COLUMNS.filter(function (c) { return scene.hasValues(c[0], false); });
    cols.splice(Math.min(cols.length, 4), 0, ['(passes)']);
    return cols;
  };
  Table.prototype.refresh = function () {
    var scene = this.scene, column = this.sortColumn, dir = this.sortDir;
    var order = scene.rows.map(function (r, i) { return i; });
    if (column) {
      var numeric = scene.rows.every(function (r, i) { var v = scene.get(i, column); return v === '' || !isNaN(num(v)); });
      order.sort(function (a, b) {
        var va = scene.get(a, column), vb = scene.get(b, column);
        if (va === '' || vb === '') return va === vb ? a - b : (va === '' ? 1 : -1);  // empty last either way
        var d = numeric ? num(va) - num(vb) : va.localeCompare(vb);
        return (d || 0) * dir || a - b;
      });
    }
    var terms = this.filter.toLowerCase().split(/\s+/).filter(Boolean), status = this.status;
    this.view = order.filter(function (i) {
      if (status && scene.get(i, 'status') !== status) return false;
      if (!terms.length) return true;
      var text = [scene.get(i, 'method'), scene.get(i, 'series'), scene.get(i, 'params'), scene.get(i, 'status'),
                  scene.get(i, 'reason'), scene.get(i, 'shard')].join(' ').toLowerCase();
      return terms.every(function (t) { return text.indexOf(t) >= 0; });
    });
    this.page = Math.min(this.page, Math.max(0, Math.ceil(this.view.length / PAGE_SIZE) - 1));
    this.render();
  };
  Table.prototype.render = function () {
    var t = this, scene = t.scene, cols = t.columns();
    var first = t.page * PAGE_SIZE, shown = t.view.slice(first, first + PAGE_SIZE);
    var maxFrame = 0;
    scene.raw.passes.forEach(function (ps) {
      var sum = 0;
      ps.forEach(function (p) { if (scene.raw.pass_names[p[0]] !== 'Frame') sum += num(p[1]) || 0; });
      maxFrame = Math.max(maxFrame, sum);
    });
    var h = '<table class="rows"><thead><tr>';
    cols.forEach(function (c) {
      var cls = c[0] === t.sortColumn ? (t.sortDir > 0 ? 'sorted-asc' : 'sorted-desc') : '';
      h += c[0] === '(passes)' ? '<th title="the passes\' medians, stacked (Frame: the whole frame)">passes</th>'
                               : '<th data-col="' + esc(c[0]) + '" class="' + cls + '">' + esc(c[0]) + '</th>';
    });
    h += '</tr></thead><tbody>';
    shown.forEach(function (i) {
      h += '<tr data-row="' + i + '"' + (i === scene.selected ? ' class="sel"' : '') + '>';
      cols.forEach(function (c) {
        if (c[0] === '(passes)') { h += '<td>' + passBar(scene, i, 150, 12, maxFrame) + '</td>'; return; }
        var v = scene.get(i, c[0]), isNum = v !== '' && !isNaN(num(v));
        var cls = c[0] === 'status' ? 'status-' + v : c[0] === 'params' ? 'params mono' : isNum ? 'num' : '';
        var extra = c[1] ? range(scene, i, c[0]) : '';
        h += '<td class="' + cls + '"' + (c[0] === 'params' || c[0] === 'reason' ? ' title="' + esc(v) + '"' : '') + '>' +
             esc(v) + (extra ? ' <span class="range">' + esc(extra.trim()) + '</span>' : '') + '</td>';
      });
      h += '</tr>';
    });
    h += '</tbody></table>';
    var pages = Math.max(1, Math.ceil(t.view.length / PAGE_SIZE));
    t.host.querySelector('.tablewrap').innerHTML = h;
    t.host.querySelector('.pageinfo').textContent = t.view.length
        ? 'rows ' + (first + 1) + '\u2013' + (first + shown.length) + ' of ' + t.view.length +
          (t.view.length !== scene.rows.length ? ' (of ' + scene.rows.length + ')' : '') + ', page ' + (t.page + 1) + ' of ' + pages
        : 'no row matches (of ' + scene.rows.length + ')';
  };
  Table.prototype.build = function () {
    var t = this, host = t.host;
    host.innerHTML = '<div class="controls"><input type="search" class="filter" placeholder="filter: method, params, status, reason">' +
        '<select class="status"><option value="">every status</option><option>Success</option><option>Unsupported</option>' +
        '<option>Failure</option></select><label><input type="checkbox" class="allcols"> every column</label>' +
        '<span class="pager"><button data-go="first">\u00ab</button> <button data-go="prev">\u2039</button> ' +
        '<button data-go="next">\u203a</button> <button data-go="last">\u00bb</button></span> <span class="pageinfo muted"></span></div>' +
        '<div class="tablewrap"></div>';
    host.querySelector('.filter').addEventListener('input', function (e) { t.filter = e.target.value; t.page = 0; t.refresh(); });
    host.querySelector('.status').addEventListener('change', function (e) { t.status = e.target.value; t.page = 0; t.refresh(); });
    host.querySelector('.allcols').addEventListener('change', function (e) { t.all = e.target.checked; t.render(); });
    host.querySelector('.pager').addEventListener('click', function (e) {
      var go = e.target.getAttribute('data-go'), last = Math.max(0, Math.ceil(t.view.length / PAGE_SIZE) - 1);
      if (!go) return;
      t.page = go === 'first' ? 0 : go === 'last' ? last : Math.max(0, Math.min(last, t.page + (go === 'next' ? 1 : -1)));
      t.render();
    });
    host.querySelector('.tablewrap').addEventListener('click', function (e) {
      var th = e.target.closest('th[data-col]');
      if (th) {
        var c = th.getAttribute('data-col');
        t.sortDir = t.sortColumn === c ? -t.sortDir : 1;
        t.sortColumn = c;
        t.refresh();
        return;
      }
      var tr = e.target.closest('tr[data-row]');
      if (tr) select(t.scene, Number(tr.getAttribute('data-row')), false);
    });
    t.refresh();
  };
  Table.prototype.reveal = function (row) {
    var k = this.view.indexOf(row);
    if (k < 0) { this.filter = ''; this.status = ''; this.host.querySelector('.filter').value = '';
                 this.host.querySelector('.status').value = ''; this.refresh(); k = this.view.indexOf(row); }
    this.page = Math.floor(k / PAGE_SIZE);
    this.render();
  };

  // A row's passes as one stacked bar: the method's own passes in colour, shared ones grey.
  function passColour(scene, p) {
    var shared = scene.raw.pass_shared[p], k = 0;
    for (var q = 0; q < p; ++q) if (scene.raw.pass_shared[q] === shared) ++k;
    return shared ? PASS_SHARED[k % PASS_SHARED.length] : PASS_OWN[k % PASS_OWN.length];
  }
  function passBar(scene, row, w, h, scale) {
    var ps = scene.raw.passes[row] || [], x = 0, s = '';
    if (!ps.length || !(scale > 0)) return '';
    ps.forEach(function (p) {
      var name = scene.raw.pass_names[p[0]], v = num(p[1]);
      if (name === 'Frame' || !(v > 0)) return;
      var bw = v / scale * w;
      s += '<rect x="' + x.toFixed(2) + '" width="' + Math.max(bw, 0.5).toFixed(2) + '" height="' + h + '" fill="' +
           passColour(scene, p[0]) + '"><title>' + esc(name + ': ' + p[1] + ' ms') + '</title></rect>';
      x += bw;
    });
    return '<svg class="passbar" width="' + w + '" height="' + h + '">' + s + '</svg>';
  }
  function passLegend(scene) {
    return scene.raw.pass_names.map(function (n, p) {
      if (n === 'Frame') return '';
      return '<span><i class="swatch" style="background:' + passColour(scene, p) + '"></i>' + esc(n) +
             (scene.raw.pass_shared[p] ? ' <span class="muted">(shared)</span>' : '') + '</span>';
    }).join('');
  }

  // ---- image comparison: reference, the method's image, its error map; flip, slider, zoom
  function Viewer(scene, host) {
    this.scene = scene;
    this.host = host;
    this.mode = 'method';
    this.zoom = 0;  // 0: fit
    this.split = 50;
  }
  Viewer.prototype.build = function () {
    var v = this, host = v.host;
    host.innerHTML = '<div class="controls modes"><b class="which"></b>' +
        '<button data-mode="reference">reference</button><button data-mode="method">method</button>' +
        '<button data-mode="error">error map</button><button data-mode="slider">slider</button>' +
        '<button data-flip="1" title="switch between the reference and the method (key F over the image)">flip</button>' +
        '<label>zoom <select class="zoom"><option value="0">fit</option><option value="1">1x</option><option value="2">2x</option>' +
        '<option value="4">4x</option><option value="8">8x</option><option value="16">16x</option></select></label>' +
        '<input type="range" class="split" min="0" max="100" value="50" title="slider: reference left, method right">' +
        '<span class="pixel muted mono"></span></div>' +
        '<div class="stage" tabindex="0"><img class="base" alt=""><img class="top" alt="" hidden></div>' +
        '<p class="muted note">Error map: false-colour |\u0394L| luminance against the reference, full scale 10 % of display white.</p>';
    host.querySelector('.modes').addEventListener('click', function (e) {
      var m = e.target.getAttribute('data-mode');
      if (m) v.show(m);
      if (e.target.getAttribute('data-flip')) v.flip();
    });
    host.querySelector('.zoom').addEventListener('change', function (e) { v.zoom = Number(e.target.value); v.layout(); });
    host.querySelector('.split').addEventListener('input', function (e) { v.split = Number(e.target.value); v.layout(); });
    var stage = host.querySelector('.stage');
    stage.addEventListener('keydown', function (e) { if (e.key === 'f' || e.key === 'F') v.flip(); });
    stage.addEventListener('mousemove', function (e) {
      var img = host.querySelector('img.base'), r = img.getBoundingClientRect();
      if (!img.naturalWidth || !r.width) return;
      var x = Math.floor((e.clientX - r.left) / r.width * img.naturalWidth), y = Math.floor((e.clientY - r.top) / r.height * img.naturalHeight);
      host.querySelector('.pixel').textContent = x >= 0 && y >= 0 && x < img.naturalWidth && y < img.naturalHeight ? 'pixel ' + x + ', ' + y : '';
      if (v.mode === 'slider' && e.buttons === 1) { v.split = Math.round((e.clientX - r.left) / r.width * 100); v.layout(); }
    });
    host.querySelector('img.base').addEventListener('load', function () { v.layout(); });
  };
  Viewer.prototype.images = function () {
    var imgs = this.scene.raw.images[this.scene.selected];
    return imgs ? { reference: imgs[0], method: imgs[1], error: imgs[2] } : null;
  };
  Viewer.prototype.flip = function () { this.show(this.mode === 'reference' ? 'method' : 'reference'); };
  Viewer.prototype.show = function (mode) {
    var v = this, host = v.host, imgs = v.images(), scene = v.scene, row = scene.selected;
    v.mode = mode;
    host.querySelector('.which').textContent = row >= 0 ? scene.methodKey(row) + ' ' + scene.get(row, 'params') + ': ' : '';
    var base = host.querySelector('img.base'), top = host.querySelector('img.top');
    var src = !imgs ? null : mode === 'slider' ? imgs.reference : imgs[mode];
    host.querySelector('.stage').hidden = !src;
    if (src && base.getAttribute('src') !== src) base.setAttribute('src', src);
    base.setAttribute('data-kind', mode === 'slider' ? 'reference' : mode);
    top.hidden = mode !== 'slider' || !imgs || !imgs.method;
    if (!top.hidden && top.getAttribute('src') !== imgs.method) top.setAttribute('src', imgs.method);
    host.querySelector('.split').hidden = mode !== 'slider';
    Array.prototype.forEach.call(host.querySelectorAll('[data-mode]'), function (b) {
      b.classList.toggle('on', b.getAttribute('data-mode') === mode);
      b.disabled = !imgs || !imgs[b.getAttribute('data-mode') === 'slider' ? 'method' : b.getAttribute('data-mode')];
    });
    v.layout();
  };
  Viewer.prototype.layout = function () {
    var host = this.host, base = host.querySelector('img.base'), top = host.querySelector('img.top');
    var w = base.naturalWidth, zoom = this.zoom;
    if (!zoom && w) zoom = Math.max(1, Math.floor(Math.min(512, host.clientWidth || 512) / w));
    [base, top].forEach(function (img) { img.style.width = w ? w * zoom + 'px' : ''; });
    top.style.clipPath = 'inset(0 0 0 ' + this.split + '%)';
  };

  // ---- per scene
  function select(scene, row, reveal) {
    scene.selected = row;
    var sec = document.getElementById(scene.id);
    Array.prototype.forEach.call(sec.querySelectorAll('.pt.sel, tr.sel'), function (e) { e.classList.remove('sel'); });
    Array.prototype.forEach.call(sec.querySelectorAll('[data-row="' + row + '"]'), function (e) {
      if (e.classList.contains('pt') || e.tagName === 'TR') e.classList.add('sel');
    });
    if (reveal) scene.table.reveal(row);
    scene.viewer.show(scene.viewer.mode === 'slider' ? 'slider' : 'method');
    details(scene, row);
  }
  function kvTable(pairs) {
    return '<table class="kv">' + pairs.filter(function (p) { return p[1] !== '' && p[1] !== undefined && p[1] !== null; })
        .map(function (p) { return '<tr><th>' + esc(p[0]) + '</th><td>' + esc(p[1]) + '</td></tr>'; }).join('') + '</table>';
  }
  function details(scene, row) {
    var host = document.querySelector('#' + scene.id + ' .detail');
    if (row < 0) { host.innerHTML = ''; return; }
    var ps = scene.raw.passes[row] || [], counters = scene.get(row, 'method_stats');
    var h = '<h3>Row: ' + esc(scene.methodKey(row)) + ' <span class="mono">' + esc(scene.get(row, 'params')) + '</span></h3>';
    h += '<div class="charts"><div><h4>Passes (median, min\u2013max, ms)</h4>';
    h += ps.length ? kvTable(ps.map(function (p) {
      var n = scene.raw.pass_names[p[0]];
      return [n + (n === 'Frame' ? ' (whole frame)' : scene.raw.pass_shared[p[0]] ? ' (shared)' : ''),
              p[1] + (p[2] !== '' ? '  [' + p[2] + '\u2013' + p[3] + ']' : '')];
    })) : '<p class="muted">no passes.csv rows</p>';
    h += '</div><div><h4>Work counters and method figures</h4>';
    h += counters ? kvTable(counters.split(';').map(function (kv) { var k = kv.indexOf('='); return [kv.slice(0, k), kv.slice(k + 1)]; }))
                  : '<p class="muted">none</p>';
    h += '</div></div><details><summary>every column of this row</summary>' +
         kvTable(scene.raw.columns.map(function (c) { return [c, scene.get(row, c)]; })) + '</details>';
    host.innerHTML = h;
  }
  function problemsList(scene) {
    var bad = [];
    scene.rows.forEach(function (r, i) { if (scene.get(i, 'status') !== 'Success') bad.push(i); });
    if (!bad.length) return '<p class="muted">Every row succeeded.</p>';
    var shown = bad.slice(0, 200);
    return '<ul class="problems">' + shown.map(function (i) {
      return '<li data-row="' + i + '"><span class="status-' + esc(scene.get(i, 'status')) + '">' + esc(scene.get(i, 'status')) +
             '</span> <b>' + esc(scene.methodKey(i)) + '</b> <span class="mono">' + esc(scene.get(i, 'params')) + '</span>: ' +
             esc(scene.get(i, 'reason') || '(no reason given)') + '</li>';
    }).join('') + '</ul>' + (bad.length > shown.length ? '<p class="muted">and ' + (bad.length - shown.length) +
        ' more (filter the table by status)</p>' : '');
  }
  function provenance(scene) {
    return scene.raw.sources.map(function (k) {
      var src = data.sources[k], m = src.meta;
      var h = '<h4>Folder <a href="' + esc(src.href) + '/">' + esc(src.folder) + '</a> <span class="muted">(' + src.rows + ' rows' +
              (src.passes_csv ? ', passes.csv' : '') + (src.frames_csv ? ', frames.csv' : '') + ')</span></h4>';
      if (!m) return h + '<p class="muted">no meta.json</p>';
      var b = m.build || {}, gl = m.gl || {}, egl = m.egl || {}, cpu = m.cpu || {}, timer = m.timer || {}, ref = m.reference || {};
      var sceneMeta = m.scene || {};
      h += kvTable([
        ['renderer', [gl.renderer, gl.version, gl.vendor].filter(Boolean).join('; ')],
        ['EGL', [egl.vendor, egl.version, egl.platform].filter(Boolean).join('; ')],
        ['build', [b.type, b.compiler, b.flags, b.sanitizers && 'sanitizers ' + b.sanitizers,
                   b.assertions !== undefined ? 'assertions ' + b.assertions : ''].filter(Boolean).join('; ')],
        ['revision', m.git_sha || ''], ['date', m.date || ''], ['status', m.status || ''],
        ['command line', m.command_line || ''],
        ['CPU', [cpu.model, cpu.hardware_threads && cpu.hardware_threads + ' hardware threads'].filter(Boolean).join('; ') +
                (m.lp_num_threads ? '; LP_NUM_THREADS ' + m.lp_num_threads : '')],
        ['size', m.width ? m.width + 'x' + m.height : ''],
        ['frames', m.frames !== undefined ? m.frames + ' measured after ' + m.warmup + ' warm-up, ' + m.rounds + ' round(s), seed ' + m.seed : ''],
        ['timer', [timer.strategy, timer.reason].filter(Boolean).join(': ')],
        ['reference', ref.method ? ref.method + ':' + ref.params + (ref.cached !== undefined ? (ref.cached ? ' (from the cache)' : ' (computed)') : '') : ''],
        ['scene', [sceneMeta.source, sceneMeta.effects, sceneMeta.triangles !== undefined ? sceneMeta.triangles + ' triangles' : '',
                   sceneMeta.animation ? sceneMeta.animation.description : ''].filter(Boolean).join('; ')],
        ['equal quality', m.equal_quality ? 'errors against ' + m.equal_quality.error_against + (m.equal_quality.why ? ' (' + m.equal_quality.why + ')' : '') : ''],
        ['merged', m.shards ? m.shards.length + ' shard(s), ' + m.status + (m.missing && m.missing.length ? ', missing: ' + m.missing.join(', ') : '') : '']]);
      if (m.shards && m.shards.length) {
        h += '<details><summary>shards</summary><table class="rows"><tr><th>id</th><th>status</th><th>host</th><th>renderer</th>' +
             '<th>revision</th><th>date</th><th>rows</th><th>command line</th></tr>' + m.shards.map(function (s) {
               return '<tr><td>' + esc(s.id) + '</td><td>' + esc(s.status || '') + '</td><td>' + esc(s.host || '') + '</td><td>' +
                      esc(s.renderer || '') + '</td><td>' + esc(s.git_sha || '') + '</td><td>' + esc(s.date || '') + '</td><td>' +
                      esc(s.rows === undefined ? '' : s.rows) + '</td><td class="mono">' + esc((s.meta && s.meta.command_line) || '') + '</td></tr>';
             }).join('') + '</table></details>';
      }
      return h + '<details><summary>meta.json</summary><pre class="mono">' + esc(JSON.stringify(m, null, 1).slice(0, 200000)) + '</pre></details>';
    }).join('');
  }
  function framesBlock(scene) {
    var fr = scene.raw.frames;
    if (!fr) return '';
    var h = '<h3>Over the animation</h3>';
    scene.raw.videos.forEach(function (v) {
      h += '<p><video controls muted loop preload="metadata" src="' + esc(v) + '"></video><br><span class="muted">' + esc(v) + '</span></p>';
    });
    var err = [], time = [];
    fr.forEach(function (frames, i) {
      if (!frames.length) return;
      var label = scene.methodKey(i) + ' ' + scene.get(i, 'params');
      var e = frames.map(function (f) { return [num(f[1]), num(f[3])]; }).filter(function (p) { return isFinite(p[0]) && positive(p[1]); });
      var t = frames.map(function (f) { return [num(f[1]), num(f[2])]; }).filter(function (p) { return isFinite(p[0]) && positive(p[1]); });
      if (e.length) err.push({ row: i, pts: e, colour: scene.colour(i), label: label });
      if (t.length) time.push({ row: i, pts: t, colour: scene.colour(i), label: label });
    });
    return h + '<div class="charts">' + lineChart(scene.raw.name + ': L_s RMSE per frame', 'time in the animation (s)',
        'ls_rmse, log', true, err) + lineChart(scene.raw.name + ': frame time', 'time in the animation (s)', 'frame time (ms)', false, time) +
        '</div>';
  }
  function sceneSection(scene) {
    var raw = scene.raw, counts = { Success: 0, Unsupported: 0, Failure: 0 };
    scene.rows.forEach(function (r, i) { var st = scene.get(i, 'status'); counts[st] = (counts[st] || 0) + 1; });
    var sec = el('section', { cls: 'scene', id: scene.id, 'data-scene': raw.name });
    var effects = scene.get(0, 'effects'), renderers = {};
    scene.rows.forEach(function (r, i) { renderers[scene.get(i, 'renderer')] = 1; });
    var h = '<h2>' + esc(raw.name) + '</h2><div class="counts">' + Object.keys(counts).map(function (k) {
      return '<span class="status-' + esc(k) + '">' + counts[k] + ' ' + esc(k) + '</span>';
    }).join('') + '<span class="muted">' + esc(effects) + '</span><span class="muted">' +
        esc(Object.keys(renderers).filter(Boolean).join(', ')) + '</span></div>';
    h += '<h3>Error against time</h3><div class="controls"><label>error <select class="metric">' +
         METRICS.filter(function (m) { return scene.hasValues(m, true); }).map(function (m) {
           return '<option' + (m === scene.metric ? ' selected' : '') + '>' + m + '</option>';
         }).join('') + '</select></label><span class="muted">log-log; circled: the Pareto front (no other row is both faster ' +
         'and more accurate); hover a point for its row, click to select it</span></div>' +
         '<div class="charts chartbox"></div><div class="legend">' + scene.methodKeys.filter(function (k) {
           return scene.rows.some(function (r, i) { return scene.methodKey(i) === k && scene.get(i, 'status') === 'Success'; });
         }).map(function (k) {
           return '<span><i class="swatch" style="background:' + PALETTE[scene.methodKeys.indexOf(k) % PALETTE.length] + '"></i>' + esc(k) + '</span>';
         }).join('') + '</div>';
    h += '<h3>Rows</h3><div class="legend passlegend">' + passLegend(scene) + '</div><div class="table"></div>';
    h += '<h3>Images</h3><div class="viewer"></div><div class="detail"></div>';
    h += framesBlock(scene);
    h += '<h3>Unsupported and failed rows</h3>' + problemsList(scene);
    h += '<h3>Provenance</h3>' + provenance(scene);
    sec.innerHTML = h;
    return sec;
  }
  function drawCharts(scene) {
    var box = document.querySelector('#' + scene.id + ' .chartbox');
    if (!scene.metric) { box.innerHTML = '<p class="muted">No error values (run without a reference?).</p>'; return; }
    box.innerHTML = ['scatter_ms', 'frame_median_ms'].filter(function (c) { return scene.col[c] !== undefined; })
        .map(function (c) { return '<div data-time="' + c + '">' + errorChart(scene, c) + '</div>'; }).join('');
  }
  function wire(scene) {
    var sec = document.getElementById(scene.id);
    scene.table = new Table(scene, sec.querySelector('.table'));
    scene.table.build();
    scene.viewer = new Viewer(scene, sec.querySelector('.viewer'));
    scene.viewer.build();
    drawCharts(scene);
    sec.querySelector('.metric') && sec.querySelector('.metric').addEventListener('change', function (e) {
      scene.metric = e.target.value;
      drawCharts(scene);
    });
    sec.addEventListener('mouseover', function (e) {
      var t = e.target.closest('[data-row]');
      if (t && (t.classList.contains('pt') || t.tagName === 'polyline')) showTip(e, scene.describe(Number(t.getAttribute('data-row'))));
    });
    sec.addEventListener('mouseout', hideTip);
    sec.addEventListener('click', function (e) {
      var t = e.target.closest('.pt[data-row], .problems li[data-row], polyline[data-row]');
      if (t) select(scene, Number(t.getAttribute('data-row')), true);
    });
    // Start on the row with images nearest the middle of the Pareto front, else the first with images.
    var withImages = scene.rows.map(function (r, i) { return i; }).filter(function (i) { return scene.raw.images[i]; });
    var start = -1;
    if (scene.metric) {
      var front = paretoFront(scene.plottable('scatter_ms', scene.metric)).filter(function (p) { return scene.raw.images[p.row]; });
      if (front.length) start = front[Math.floor(front.length / 2)].row;
    }
    if (start < 0 && withImages.length) start = withImages[0];
    if (start < 0) sec.querySelector('.viewer').innerHTML = '<p class="muted">No images (run without --no-images to get them).</p>';
    else select(scene, start, false);
  }

  // ---- the page
  var scenes = data.scenes.map(function (raw, i) { return new Scene(raw, i); });
  var top = document.getElementById('top');
  var total = scenes.reduce(function (n, s) { return n + s.rows.length; }, 0);
  top.innerHTML = '<h1>vshadow report: ' + esc(data.title) + '</h1><div class="sub">' + esc(data.dir) + ' \u00b7 ' + total +
      ' rows in ' + scenes.length + ' scene(s) from ' + data.sources.length + ' folder(s) \u00b7 generated ' + esc(data.generated) +
      ' by revision ' + esc(data.generator_revision) + '</div>' + (scenes.length > 1 ? '<nav class="scenes">' + scenes.map(function (s) {
        return '<a href="#' + s.id + '">' + esc(s.raw.name) + '</a>';
      }).join('') + '</nav>' : '') + (data.warnings.length ? '<ul class="warnings">' + data.warnings.map(function (w) {
        return '<li>' + esc(w) + '</li>';
      }).join('') + '</ul>' : '');
  var main = document.getElementById('report');
  main.innerHTML = '';
  scenes.forEach(function (s) { main.appendChild(sceneSection(s)); wire(s); });
  var renderMs = performance.now() - started;

  // ---- self-test (#selftest): the checks the test suite reads from pre#selftest
  function selfTest() {
    var checks = [], steps = [];
    function check(name, ok, detail) { checks.push({ name: name, ok: !!ok, detail: detail === undefined ? '' : String(detail) }); }
    function later(f) { steps.push(f); }
    function visibleRows(scene) {
      return Array.prototype.map.call(document.querySelectorAll('#' + scene.id + ' .tablewrap tbody tr'), function (tr) {
        return Number(tr.getAttribute('data-row'));
      });
    }
    function waitImage(img, then) {
      var waited = 0;
      (function poll() {
        if (img.complete || waited > 5000) return then();
        waited += 50;
        setTimeout(poll, 50);
      })();
    }
    scenes.forEach(function (scene) {
      var sec = document.getElementById(scene.id), name = scene.raw.name;
      // Every row once in the table's model; the pages cover them all.
      var seen = {};
      scene.table.view.forEach(function (i) { seen[i] = (seen[i] || 0) + 1; });
      check(name + ': every row once in the table', scene.table.view.length === scene.rows.length &&
            Object.keys(seen).every(function (k) { return seen[k] === 1; }), scene.table.view.length + ' of ' + scene.rows.length);
      check(name + ': first page rendered', visibleRows(scene).length === Math.min(PAGE_SIZE, scene.rows.length));
      if (scene.metric) {
        ['scatter_ms', 'frame_median_ms'].forEach(function (c) {
          if (scene.col[c] === undefined) return;
          var expected = scene.plottable(c, scene.metric).length;
          var drawn = sec.querySelectorAll('[data-time="' + c + '"] circle.pt').length;
          check(name + ': a chart point per plottable row (' + c + ')', drawn === expected && expected > 0, drawn + ' of ' + expected);
          var rows = {};
          Array.prototype.forEach.call(sec.querySelectorAll('[data-time="' + c + '"] circle.pt'), function (p) { rows[p.getAttribute('data-row')] = 1; });
          check(name + ': chart points are distinct rows (' + c + ')', Object.keys(rows).length === drawn);
          check(name + ': Pareto front marked (' + c + ')', sec.querySelectorAll('[data-time="' + c + '"] circle.front').length > 0);
        });
      }
      // Hovering a point shows its row: method, params, error and times.
      var point = sec.querySelector('circle.pt');
      if (point) {
        var r = Number(point.getAttribute('data-row')), box = point.getBoundingClientRect();
        point.dispatchEvent(new MouseEvent('mouseover', { bubbles: true, clientX: box.left + 2, clientY: box.top + 2 }));
        var tip = tooltip.hidden ? '' : tooltip.textContent;
        check(name + ': hovering a point shows its row', tip.indexOf(scene.get(r, 'params')) >= 0 &&
              tip.indexOf(scene.get(r, 'scatter_ms')) >= 0 && tip.indexOf(scene.methodKey(r)) === 0, tip.split('\n')[0]);
        point.dispatchEvent(new MouseEvent('mouseout', { bubbles: true }));
      }
      var nonSuccess = scene.rows.filter(function (r, i) { return scene.get(i, 'status') !== 'Success'; }).length;
      check(name + ': Unsupported and failed rows listed', sec.querySelectorAll('.problems li').length === Math.min(200, nonSuccess),
            nonSuccess);
      // Sorting by scattering time reorders the rows: ascending, then descending.
      later(function () {
        var before = visibleRows(scene).join(',');
        var th = sec.querySelector('th[data-col="scatter_ms"]');
        if (!th) return check(name + ': sort by scatter_ms', false, 'no scatter_ms column');
        th.click();
        var asc = visibleRows(scene), values = asc.map(function (i) { return num(scene.get(i, 'scatter_ms')); });
        var finite = values.filter(function (v) { return !isNaN(v); });
        check(name + ': sorting scatter_ms ascending', finite.every(function (v, k) { return !k || finite[k - 1] <= v; }) &&
              (asc.join(',') !== before || scene.rows.length < 2), finite.slice(0, 5).join(' '));
        sec.querySelector('th[data-col="scatter_ms"]').click();
        var desc = visibleRows(scene).map(function (i) { return num(scene.get(i, 'scatter_ms')); }).filter(function (v) { return !isNaN(v); });
        check(name + ': sorting scatter_ms descending', desc.every(function (v, k) { return !k || desc[k - 1] >= v; }), desc.slice(0, 5).join(' '));
      });
      // Filtering by a method keeps only its rows.
      later(function () {
        var method = scene.get(0, 'method'), input = sec.querySelector('.filter');
        input.value = method;
        input.dispatchEvent(new Event('input'));
        var shown = visibleRows(scene);
        check(name + ': filter by method', shown.length > 0 && shown.every(function (i) {
          return [scene.get(i, 'method'), scene.get(i, 'params'), scene.get(i, 'status'), scene.get(i, 'reason'),
                  scene.get(i, 'series'), scene.get(i, 'shard')].join(' ').toLowerCase().indexOf(method.toLowerCase()) >= 0;
        }), shown.length);
        input.value = '';
        input.dispatchEvent(new Event('input'));
      });
      // The image toggle switches images, and each loads.
      var imgs = scene.viewer.images();
      if (imgs && imgs.reference && imgs.method) {
        var base = sec.querySelector('.viewer img.base'), srcs = {};
        ['reference', 'method', 'error'].forEach(function (mode) {
          if (!imgs[mode]) return;
          later(function (next) {
            sec.querySelector('.viewer [data-mode="' + mode + '"]').click();
            srcs[mode] = base.getAttribute('src');
            waitImage(base, function () {
              check(name + ': image toggle shows ' + mode, srcs[mode] === imgs[mode] && base.naturalWidth > 0, srcs[mode]);
              next();
            });
          });
        });
        later(function () {
          sec.querySelector('.viewer [data-flip]').click();
          var flipped = base.getAttribute('src');
          check(name + ': flip switches image', flipped !== srcs.error && (flipped === imgs.reference || flipped === imgs.method), flipped);
          check(name + ': toggle gives distinct images', srcs.reference !== srcs.method);
          sec.querySelector('.viewer [data-mode="slider"]').click();
          check(name + ': slider shows both', !sec.querySelector('.viewer img.top').hidden);
        });
      }
      if (scene.raw.frames) check(name + ': frames charts drawn', sec.querySelectorAll('polyline[data-row]').length > 0);
      Array.prototype.forEach.call(sec.querySelectorAll('video'), function (video) {
        later(function (next) {
          var waited = 0;
          (function poll() {
            if (video.readyState >= 1 || video.error || waited > 5000) {
              check(name + ': video loads', video.readyState >= 1 && !video.error, video.getAttribute('src'));
              return next();
            }
            waited += 50;
            setTimeout(poll, 50);
          })();
        });
      });
    });
    (function run() {
      var step = steps.shift();
      if (!step) return finish();
      if (step.length) step(function () { setTimeout(run, 0); });
      else { step(); setTimeout(run, 0); }
    })();
    function finish() {
      var verdict = {
        ok: checks.every(function (c) { return c.ok; }) && !problems.length,
        checks: checks, errors: problems, render_ms: Math.round(renderMs), rows: total, scenes: scenes.length,
        points: document.querySelectorAll('circle.pt').length
      };
      var pre = document.getElementById('selftest');
      pre.textContent = JSON.stringify(verdict);
      pre.hidden = false;
      document.title += ' [selftest done]';
    }
  }
  if (location.hash === '#selftest') setTimeout(selfTest, 0);
})();
