// The sweep map: draws the JSON data of sweep_view.cpp on a canvas. Texts from the model are
// shown through textContent only.
(function () {
  'use strict';
  var errors = [];
  function reportError(text) {
    errors.push(String(text));
    var box = document.getElementById('stiffmsa-errors');
    box.hidden = false;
    box.textContent = errors.join('\n');
  }
  window.addEventListener('error', function (event) { reportError(event.message); });
  var consoleError = console.error;
  console.error = function () { reportError(Array.prototype.join.call(arguments, ' ')); consoleError.apply(console, arguments); };

  var data = JSON.parse(document.getElementById('stiffmsa-data').textContent);
  function decode(base64) {
    var text = atob(base64), bytes = new Uint8Array(text.length);
    for (var i = 0; i < text.length; ++i) bytes[i] = text.charCodeAt(i);
    return new Float32Array(bytes.buffer);
  }
  function element(tag, text, className) {
    var node = document.createElement(tag);
    if (text !== undefined) node.textContent = text;
    if (className) node.className = className;
    return node;
  }
  function number(value) {
    if (!isFinite(value)) return value > 0 ? '∞' : '—';
    var magnitude = Math.abs(value);
    return value === 0 ? '0' : magnitude >= 1e-3 && magnitude < 1e5 ? String(+value.toPrecision(4)) : value.toExponential(3);
  }

  data.parameters.forEach(function (p) { p.data = decode(p.values); });
  data.columns.forEach(function (c) { c.data = decode(c.values); });
  var ellipsoids = data.ellipsoids ? data.ellipsoids.map(decode) : null;
  var poses = data.poses;

  // A 2-D grid is a map; a 1-D grid or a list of poses a strip, one cell per pose.
  var grid = data.grid;
  var nx = grid.length >= 1 ? grid[0].count : poses;
  var ny = grid.length >= 2 ? grid[1].count : 1;
  function poseAt(ix, iy) { return ix + nx * iy; }

  document.title = data.model + ' — stiffmsa sweep';
  document.getElementById('title').textContent = data.model;
  document.getElementById('subtitle').textContent = poses + ' poses over ' +
    data.parameters.map(function (p) { return p.name + (p.unit ? ' (' + p.unit + ')' : ''); }).join(', ');

  var select = document.getElementById('column');
  data.columns.forEach(function (c, k) { var o = element('option', c.name + ' (' + c.unit + ')'); o.value = k; select.appendChild(o); });
  var chosen = 0;
  select.addEventListener('change', function () { chosen = +select.value; draw(); });

  // Viridis, as the PNG maps of --plot.
  var stops = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
  function colour(t) {
    t = Math.max(0, Math.min(1, t)) * (stops.length - 1);
    var i = Math.min(Math.floor(t), stops.length - 2), f = t - i;
    return stops[i].map(function (c, k) { return Math.round(c + f * (stops[i + 1][k] - c)); });
  }

  var canvas = document.getElementById('heatmap');
  var context = canvas.getContext('2d');
  var margin = { left: 70, right: 170, top: 20, bottom: 50 };
  var cell = { w: 1, h: 1 };
  function draw() {
    var wrap = document.getElementById('heatmap-wrap');
    canvas.width = wrap.clientWidth - 2;
    canvas.height = ny === 1 ? Math.min(wrap.clientHeight - 2, 220) : wrap.clientHeight - 2;
    var width = canvas.width - margin.left - margin.right, height = canvas.height - margin.top - margin.bottom;
    cell.w = width / nx; cell.h = height / ny;
    // Square cells where both axes are lengths of one unit, so that the map is not distorted.
    var units = data.parameters.map(function (p) { return p.unit; });
    if (ny > 1 && units.length >= 2 && units[0] && units[0] === units[1] && grid.length >= 2) {
      var perUnit = Math.min(width / Math.abs(grid[0].stop - grid[0].start || 1), height / Math.abs(grid[1].stop - grid[1].start || 1));
      cell.w = perUnit * Math.abs(grid[0].stop - grid[0].start || 1) / nx;
      cell.h = perUnit * Math.abs(grid[1].stop - grid[1].start || 1) / ny;
      width = cell.w * nx; height = cell.h * ny;
    }
    var column = data.columns[chosen], values = column.data;
    var low = Infinity, high = -Infinity;
    for (var i = 0; i < values.length; ++i) if (isFinite(values[i])) { low = Math.min(low, values[i]); high = Math.max(high, values[i]); }
    var logarithmic = low > 0 && high / low > 100;
    var position = function (v) {
      if (!(high > low)) return 0.5;
      return logarithmic ? Math.log(v / low) / Math.log(high / low) : (v - low) / (high - low);
    };
    context.clearRect(0, 0, canvas.width, canvas.height);
    for (var iy = 0; iy < ny; ++iy) {
      for (var ix = 0; ix < nx; ++ix) {
        var v = values[poseAt(ix, iy)];
        var rgb = isFinite(v) ? colour(position(v)) : [200, 200, 200];
        context.fillStyle = 'rgb(' + rgb.join(',') + ')';
        // y grows upwards, as on the PNG maps.
        context.fillRect(margin.left + ix * cell.w, margin.top + (ny - 1 - iy) * cell.h, Math.ceil(cell.w), Math.ceil(cell.h));
      }
    }
    context.fillStyle = '#222';
    context.font = '12px sans-serif';
    var xName = grid.length ? grid[0].parameter : 'pose', yName = grid.length >= 2 ? grid[1].parameter : '';
    context.fillText(xName + (grid.length ? ' ' + number(grid[0].start) + ' … ' + number(grid[0].stop) : ' 1 … ' + poses),
                     margin.left, margin.top + height + 30);
    if (yName) {
      context.save();
      context.translate(16, margin.top + height);
      context.rotate(-Math.PI / 2);
      context.fillText(yName + ' ' + number(grid[1].start) + ' … ' + number(grid[1].stop), 0, 0);
      context.restore();
    }
    // The colour bar, with its ends' values.
    var barLeft = margin.left + width + 15;
    for (var k = 0; k < height; ++k) {
      context.fillStyle = 'rgb(' + colour(1 - k / height).join(',') + ')';
      context.fillRect(barLeft, margin.top + k, 16, 1.5);
    }
    context.fillStyle = '#222';
    context.fillText(number(high) + ' ' + column.unit, barLeft + 20, margin.top + 10);
    context.fillText(number(low) + ' ' + column.unit, barLeft + 20, margin.top + height);
    document.getElementById('range').textContent = column.name + ': ' + number(low) + ' … ' + number(high) + ' ' + column.unit +
      (logarithmic ? ' (logarithmic colours)' : '') + '; grey: no value (failed pose)';
  }

  function showPose(pose) {
    var box = document.getElementById('pose');
    box.textContent = '';
    var table = element('table');
    var add = function (name, value) { var row = element('tr'); row.appendChild(element('th', name)); row.appendChild(element('td', value)); table.appendChild(row); };
    add('pose', String(pose + 1));
    data.parameters.forEach(function (p) { add(p.name, number(p.data[pose]) + (p.unit ? ' ' + p.unit : '')); });
    add('status', data.status[pose]);
    if (data.messages[pose]) add('message', data.messages[pose]);
    data.columns.forEach(function (c) { add(c.name, number(c.data[pose]) + ' ' + c.unit); });
    box.appendChild(table);
    drawEllipses(pose);
  }

  // Each end effector's translational compliance ellipsoid seen along z, y and x: the shadow
  // of {C f : |f| <= 1} on a plane is the ellipse of the 2×2 block of C·C.
  function drawEllipses(pose) {
    var view = document.getElementById('ellipses'), note = document.getElementById('ellipse-note');
    if (!ellipsoids) return;
    view.hidden = note.hidden = false;
    var c2 = view.getContext('2d');
    c2.clearRect(0, 0, view.width, view.height);
    var planes = [[0, 1, 'x-y'], [0, 2, 'x-z'], [1, 2, 'y-z']];
    var texts = [];
    ellipsoids.forEach(function (axes, e) {
      var base = 12 * pose;
      if (!isFinite(axes[base])) return;
      var values = [axes[base], axes[base + 1], axes[base + 2]];
      var largest = Math.max(values[2], 1e-300);
      // M = D diag(λ²) Dᵀ, D's columns the directions.
      var m = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
      for (var k = 0; k < 3; ++k)
        for (var r = 0; r < 3; ++r)
          for (var s = 0; s < 3; ++s) m[r][s] += values[k] * values[k] / (largest * largest) * axes[base + 3 + 3 * k + r] * axes[base + 3 + 3 * k + s];
      planes.forEach(function (plane, p) {
        var a = m[plane[0]][plane[0]], b = m[plane[0]][plane[1]], d = m[plane[1]][plane[1]];
        var mean = (a + d) / 2, spread = Math.sqrt(Math.max(((a - d) / 2) * ((a - d) / 2) + b * b, 0));
        var major = Math.sqrt(Math.max(mean + spread, 0)), minor = Math.sqrt(Math.max(mean - spread, 0));
        var angle = 0.5 * Math.atan2(2 * b, a - d);
        var cx = 47 + 93 * p, cy = 50, radius = 38;
        c2.strokeStyle = ['#17a2b8', '#c2185b', '#2e9e4f', '#e0a100'][e % 4];
        c2.beginPath();
        c2.ellipse(cx, cy, Math.max(radius * major, 0.5), Math.max(radius * minor, 0.5), -angle, 0, 2 * Math.PI);
        c2.stroke();
        c2.fillStyle = '#555';
        c2.font = '10px sans-serif';
        c2.fillText(plane[2], cx - 8, 97);
      });
      texts.push(data.end_effectors[e] + ': principal compliances ' + values.map(number).join(', ') + ' m/N');
    });
    note.textContent = texts.join('; ') + ' (ellipses scaled to the largest)';
  }

  // The pose under the mouse, outlined over the map.
  var marker = element('div');
  marker.style.cssText = 'position:absolute;border:2px solid #fff;outline:1px solid #000;pointer-events:none;display:none';
  document.getElementById('heatmap-wrap').appendChild(marker);
  canvas.addEventListener('mousemove', function (event) {
    var rect = canvas.getBoundingClientRect();
    var ix = Math.floor((event.clientX - rect.left - margin.left) / cell.w);
    var iy = ny - 1 - Math.floor((event.clientY - rect.top - margin.top) / cell.h);
    if (!(ix >= 0 && ix < nx && iy >= 0 && iy < ny)) return;
    showPose(poseAt(ix, iy));
    marker.style.display = '';
    marker.style.left = (canvas.offsetLeft + margin.left + ix * cell.w - 2) + 'px';
    marker.style.top = (canvas.offsetTop + margin.top + (ny - 1 - iy) * cell.h - 2) + 'px';
    marker.style.width = Math.max(cell.w, 2) + 'px';
    marker.style.height = Math.max(cell.h, 2) + 'px';
  });
  window.addEventListener('resize', draw);
  draw();
  document.getElementById('stiffmsa-status').textContent = 'ready';
  window.stiffmsaShowPose = showPose;
})();
