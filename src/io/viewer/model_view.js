// The model viewer: draws the JSON data of view_html.cpp with three.js. Every text that comes
// from the model is shown through textContent, never parsed as HTML.
(function () {
  'use strict';

  // Errors are shown on the page and kept where a test can read them (#stiffmsa-errors).
  var errors = [];
  function reportError(text) {
    errors.push(String(text));
    var box = document.getElementById('stiffmsa-errors');
    box.hidden = false;
    box.textContent = errors.join('\n');
  }
  window.addEventListener('error', function (event) { reportError(event.message); });
  window.addEventListener('unhandledrejection', function (event) { reportError(event.reason); });
  var consoleError = console.error;
  console.error = function () {
    reportError(Array.prototype.join.call(arguments, ' '));
    consoleError.apply(console, arguments);
  };

  var data = JSON.parse(document.getElementById('stiffmsa-data').textContent);
  var options = parseHash();

  function parseHash() {
    var result = {};
    location.hash.replace(/^#/, '').split('&').forEach(function (pair) {
      var at = pair.indexOf('=');
      if (at > 0) result[decodeURIComponent(pair.slice(0, at))] = decodeURIComponent(pair.slice(at + 1));
    });
    return result;
  }

  function decode(base64, Type) {
    var text = atob(base64);
    var bytes = new Uint8Array(text.length);
    for (var i = 0; i < text.length; ++i) bytes[i] = text.charCodeAt(i);
    return new Type(bytes.buffer);
  }

  function element(tag, text, className) {
    var node = document.createElement(tag);
    if (text !== undefined) node.textContent = text;
    if (className) node.className = className;
    return node;
  }

  function number(value, digits) {
    if (value === null || value === undefined) return '∞';
    if (value === 0) return '0';
    var magnitude = Math.abs(value);
    return magnitude >= 1e-3 && magnitude < 1e5 ? String(+value.toPrecision(digits || 4)) : value.toExponential((digits || 4) - 1);
  }

  var colours = {
    beam: 0x4a78b5, rigid: 0x4d535c, cad: 0xe08a2e, deformed: 0xd7263d,
    roles: [0x8a9099, 0x2e9e4f, 0xe0a100, 0xc0392b],
    support: 0x2f3b4c, force: 0x1565c0, moment: 0x8e44ad, effector: 0xc2185b, ellipsoid: 0x17a2b8,
    axisLine: 0x222222, model: 0x9aa3ad
  };
  var hex = function (c) { return '#' + ('000000' + c.toString(16)).slice(-6); };

  // ---- the model's arrays --------------------------------------------------------------
  var xyz = decode(data.points.xyz, Float32Array);
  var pointCount = data.points.names.length;
  var linkCount = data.links.names.length;
  var ends = decode(data.links.ends, Int32Array);
  var kinds = decode(data.links.kinds, Int32Array);
  var sections = decode(data.links.sections, Float32Array);
  var yAxes = decode(data.links.y_axes, Float32Array);
  var size = data.size;

  function pointVector(p) { return new THREE.Vector3(xyz[3 * p], xyz[3 * p + 1], xyz[3 * p + 2]); }

  var low = new THREE.Vector3(Infinity, Infinity, Infinity), high = low.clone().negate();
  for (var p = 0; p < pointCount; ++p) { var v = pointVector(p); low.min(v); high.max(v); }
  if (pointCount === 0) { low.set(0, 0, 0); high.set(0, 0, 0); }
  var centre = low.clone().add(high).multiplyScalar(0.5);

  // Drawn sizes: markers scale with the model and with its beams' sections.
  var beamWidths = [];
  for (var i = 0; i < linkCount; ++i) if (kinds[i] === 0) beamWidths.push(Math.max(sections[3 * i], sections[3 * i + 1]));
  beamWidths.sort(function (a, b) { return a - b; });
  var typicalWidth = beamWidths.length ? beamWidths[beamWidths.length >> 1] : 0;
  var averageLength = 0;
  for (i = 0; i < linkCount; ++i) averageLength += pointVector(ends[2 * i]).distanceTo(pointVector(ends[2 * i + 1]));
  averageLength = linkCount ? averageLength / linkCount : size;
  var markerSize = Math.min(Math.max(1.5 * typicalWidth, 0.018 * size), 0.05 * size, 0.35 * averageLength || Infinity);
  var rigidThickness = 0.45 * markerSize;

  // ---- the scene -----------------------------------------------------------------------
  var container = document.getElementById('scene');
  // Antialiasing (multisampling) costs a software renderer most of its time: robots get it, large
  // models do not (the 1 000-link chain in headless Chromium: 1.6 frames per second with it, 13 without).
  var renderer = new THREE.WebGLRenderer({ antialias: linkCount <= 200 });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(window.innerWidth, window.innerHeight);
  renderer.setClearColor(0xf4f5f7);
  container.appendChild(renderer.domElement);

  var scene = new THREE.Scene();
  var camera = new THREE.PerspectiveCamera(40, window.innerWidth / window.innerHeight, size * 1e-3, size * 100);
  camera.up.set(0, 0, 1);  // models are written z up
  scene.add(new THREE.HemisphereLight(0xffffff, 0x666677, 0.75));
  var headlight = new THREE.DirectionalLight(0xffffff, 0.55);
  headlight.position.set(1, 1, 2);
  camera.add(headlight);
  scene.add(camera);

  var controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.screenSpacePanning = true;
  controls.addEventListener('change', requestRender);

  // The drawing's centre sits right of the panel, so that the panel hides none of the model.
  var panelWidth = document.getElementById('panel').offsetWidth + 8;
  function frameView() {
    var width = window.innerWidth, height = window.innerHeight;
    camera.aspect = width / height;
    if (width > 2 * panelWidth) camera.setViewOffset(width, height, -panelWidth / 2, 0, width, height);
    else camera.clearViewOffset();
    camera.updateProjectionMatrix();
  }

  function resetView() {
    // Looking from the front right and above.
    var direction = new THREE.Vector3(1.0, -1.6, 0.9).normalize();
    var flat = high.z - low.z < 1e-9 * size;
    if (flat) direction.set(0.25, -0.55, 1).normalize();  // a planar model is seen from above
    // The model's bounding sphere fills the height of the view, and its width right of the panel.
    var halfAngle = THREE.Math.degToRad(camera.fov / 2);
    var usable = Math.min(1, (window.innerWidth - panelWidth) / window.innerHeight);
    var radius = 0.5 * high.distanceTo(low) || size / 2;
    controls.target.copy(centre);
    camera.position.copy(centre).addScaledVector(direction, 1.15 * radius / Math.sin(Math.atan(Math.tan(halfAngle) * usable)));
    frameView();
    controls.update();
  }

  function material(colour, extra) {
    var parameters = { color: colour, shininess: 30 };
    for (var key in extra) parameters[key] = extra[key];
    return new THREE.MeshPhongMaterial(parameters);
  }

  // One mesh per shape and colour, whatever the number of links: the shape's copies placed by
  // their matrices and merged into one geometry. (Software WebGL, as in headless Chromium,
  // pays per instance of an InstancedMesh: 9 000 small boxes drew at 1.5 frames per second
  // instanced and at 9.7 merged, bench/README.md.)
  function fillMerged(target, geometry, matrices) {
    var source = geometry.attributes.position.array, sourceNormal = geometry.attributes.normal.array;
    var perCopy = source.length;
    var positions = target.attributes.position.array, normals = target.attributes.normal.array;
    var normalMatrix = new THREE.Matrix3(), v = new THREE.Vector3();
    for (var k = 0; k < matrices.length; ++k) {
      normalMatrix.getNormalMatrix(matrices[k]);
      for (var i = 0; i < perCopy; i += 3) {
        v.set(source[i], source[i + 1], source[i + 2]).applyMatrix4(matrices[k]);
        positions[k * perCopy + i] = v.x; positions[k * perCopy + i + 1] = v.y; positions[k * perCopy + i + 2] = v.z;
        v.set(sourceNormal[i], sourceNormal[i + 1], sourceNormal[i + 2]).applyMatrix3(normalMatrix).normalize();
        normals[k * perCopy + i] = v.x; normals[k * perCopy + i + 1] = v.y; normals[k * perCopy + i + 2] = v.z;
      }
    }
    target.attributes.position.needsUpdate = true;
    target.attributes.normal.needsUpdate = true;
    target.setDrawRange(0, (geometry.index ? geometry.index.count : source.length / 3) * matrices.length);
  }
  function mergedGeometry(geometry, copies) {
    var vertices = geometry.attributes.position.count;
    var merged = new THREE.BufferGeometry();
    merged.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * vertices * copies), 3));
    merged.setAttribute('normal', new THREE.BufferAttribute(new Float32Array(3 * vertices * copies), 3));
    var order = geometry.index ? geometry.index.array : null;
    var perCopy = order ? order.length : vertices;
    var index = new (vertices * copies > 65535 ? Uint32Array : Uint16Array)(perCopy * copies);
    for (var k = 0; k < copies; ++k)
      for (var i = 0; i < perCopy; ++i) index[k * perCopy + i] = k * vertices + (order ? order[i] : i);
    merged.setIndex(new THREE.BufferAttribute(index, 1));
    return merged;
  }
  function placed(geometry, mat, matrices) {
    var merged = mergedGeometry(geometry, matrices.length);
    fillMerged(merged, geometry, matrices);
    var mesh = new THREE.Mesh(merged, mat);
    mesh.frustumCulled = false;
    return mesh;
  }

  function anyPerpendicular(direction) {
    var other = Math.abs(direction.x) < 0.9 ? new THREE.Vector3(1, 0, 0) : new THREE.Vector3(0, 1, 0);
    return other.cross(direction).normalize();
  }

  // A matrix that maps the unit shape (axis along y, centred) onto a piece from a to b.
  function pieceMatrix(a, b, width, height, sideAxis) {
    var along = b.clone().sub(a);
    var length = along.length();
    var direction = length > 0 ? along.clone().divideScalar(length) : new THREE.Vector3(0, 0, 1);
    var side = sideAxis && sideAxis.lengthSq() > 0 ? sideAxis.clone() : anyPerpendicular(direction);
    var normal = direction.clone().cross(side);  // with side and direction, the beam's local z
    var m = new THREE.Matrix4().makeBasis(side.multiplyScalar(-width), along, normal.multiplyScalar(height));
    m.setPosition(a.clone().add(b).multiplyScalar(0.5));
    return m;
  }

  // A matrix that puts a unit shape (axis along y) at a point, its axis along `axis`.
  function placedMatrix(position, axis, radius, length) {
    var direction = axis && axis.lengthSq() > 0 ? axis.clone().normalize() : new THREE.Vector3(0, 0, 1);
    var side = anyPerpendicular(direction);
    var normal = side.clone().cross(direction);
    var m = new THREE.Matrix4().makeBasis(side.multiplyScalar(radius), direction.multiplyScalar(length), normal.multiplyScalar(radius));
    m.setPosition(position);
    return m;
  }

  // x, y, z as red, green and blue lines from the origin.
  scene.add(new THREE.AxesHelper(0.12 * size));

  var groups = { model: new THREE.Group(), deformed: new THREE.Group(), loads: new THREE.Group(), ellipsoids: new THREE.Group() };
  for (var name in groups) scene.add(groups[name]);

  // ---- links ---------------------------------------------------------------------------
  // Without a GPU (software WebGL) the triangles drawn set the frame rate: above this many,
  // links are drawn as their centre lines and the deformed shape as lines (bench/README.md).
  var mostTriangles = 400000;
  var unitCylinder = new THREE.CylinderBufferGeometry(0.5, 0.5, 1, 14, 1);
  var tubeGeometry = new THREE.CylinderBufferGeometry(0.5, 0.5, 1, 10, 1, true);  // beams: open tubes
  var pieceGeometry = new THREE.CylinderBufferGeometry(0.5, 0.5, 1, 6, 1, true);  // the deformed shape's pieces
  var solidLinks = linkCount * 20 <= mostTriangles;
  var unitBox = new THREE.BoxBufferGeometry(1, 1, 1);
  var linkMaterials = {
    beam: material(colours.beam, { transparent: true, side: THREE.DoubleSide }),
    rigid: material(colours.rigid, { transparent: true }),
    cad: material(colours.cad, { transparent: true })
  };
  (function drawLinks() {
    var round = [], square = [], rigid = [], cad = [];
    var linePositions = new Float32Array(6 * linkCount);
    for (var k = 0; k < linkCount; ++k) {
      var a = pointVector(ends[2 * k]), b = pointVector(ends[2 * k + 1]);
      linePositions.set([a.x, a.y, a.z, b.x, b.y, b.z], 6 * k);
      if (!solidLinks || a.distanceTo(b) === 0) continue;
      var kind = kinds[k];
      if (kind === 0) {
        var yAxis = new THREE.Vector3(yAxes[3 * k], yAxes[3 * k + 1], yAxes[3 * k + 2]);
        var width = Math.max(sections[3 * k], 1e-3 * size), height = Math.max(sections[3 * k + 1], 1e-3 * size);
        (sections[3 * k + 2] ? round : square).push(pieceMatrix(a, b, width, height, yAxis));
      } else if (kind === 1) {
        rigid.push(pieceMatrix(a, b, rigidThickness, rigidThickness));
      } else {
        cad.push(pieceMatrix(a, b, 1.4 * rigidThickness, 1.4 * rigidThickness));
      }
    }
    if (solidLinks) {
      if (round.length) groups.model.add(placed(tubeGeometry, linkMaterials.beam, round));
      if (square.length) groups.model.add(placed(unitBox, linkMaterials.beam, square));
      if (rigid.length) groups.model.add(placed(unitBox, linkMaterials.rigid, rigid));
      if (cad.length) groups.model.add(placed(unitBox, linkMaterials.cad, cad));
    }
    // The centre lines, so that a link thinner than a pixel still shows.
    var lines = new THREE.BufferGeometry();
    lines.setAttribute('position', new THREE.BufferAttribute(linePositions, 3));
    groups.model.add(new THREE.LineSegments(lines, new THREE.LineBasicMaterial({ color: colours.model })));
  })();

  // ---- joints and supports -------------------------------------------------------------
  // Each kind has its shape; the colour tells rigid, passive, elastic and actuated apart.
  var glyphs = {
    revolute: [{ geometry: unitCylinder, radius: 1.0, length: 1.3, axis: 0 }],
    prismatic: [{ geometry: unitBox, radius: 0.9, length: 2.4, axis: 0 }],
    cylindrical: [{ geometry: unitCylinder, radius: 0.7, length: 2.4, axis: 0 }],
    universal: [{ geometry: unitCylinder, radius: 0.55, length: 2.0, axis: 0 }, { geometry: unitCylinder, radius: 0.55, length: 2.0, axis: 1 }],
    spherical: [{ geometry: new THREE.SphereBufferGeometry(0.5, 20, 14), radius: 1.4, length: 1.4, axis: -1 }],
    planar: [{ geometry: unitCylinder, radius: 2.0, length: 0.3, axis: 0 }],
    rigid: [{ geometry: unitBox, radius: 0.8, length: 0.8, axis: -1 }],
    custom: [{ geometry: new THREE.OctahedronBufferGeometry(0.7), radius: 1.2, length: 1.2, axis: -1 }]
  };
  var roleMaterials = colours.roles.map(function (c) { return material(c); });
  var axisLines = [];

  function drawConnections(list, isSupport) {
    var at = decode(list.at, Int32Array), role = decode(list.role, Int32Array), axes = decode(list.axes, Float32Array);
    var buckets = {};
    var pyramids = [];
    for (var k = 0; k < list.names.length; ++k) {
      if (at[k] < 0) continue;
      var position = pointVector(at[k]);
      var type = list.types[k];
      var axis = [new THREE.Vector3(axes[6 * k], axes[6 * k + 1], axes[6 * k + 2]),
                  new THREE.Vector3(axes[6 * k + 3], axes[6 * k + 4], axes[6 * k + 5])];
      if (isSupport) {
        // The ground: a pyramid under the point; a support that lets something move also
        // shows its joint.
        pyramids.push(placedMatrix(position.clone().add(new THREE.Vector3(0, 0, -0.9 * markerSize)), new THREE.Vector3(0, 0, 1), 1.6 * markerSize, 1.8 * markerSize));
        if (type === 'rigid') continue;
      }
      (glyphs[type] || glyphs.custom).forEach(function (glyph, part) {
        var key = type + '/' + part + '/' + role[k];
        (buckets[key] = buckets[key] || { glyph: glyph, role: role[k], matrices: [] });
        var direction = glyph.axis >= 0 ? axis[glyph.axis] : null;
        buckets[key].matrices.push(placedMatrix(position, direction, glyph.radius * markerSize, glyph.length * markerSize));
        if (direction && direction.lengthSq() > 0)
          axisLines.push(position.clone().addScaledVector(direction, -2.2 * markerSize), position.clone().addScaledVector(direction, 2.2 * markerSize));
      });
    }
    for (var key in buckets)
      groups.model.add(placed(buckets[key].glyph.geometry, roleMaterials[buckets[key].role], buckets[key].matrices));
    if (pyramids.length) groups.model.add(placed(new THREE.ConeBufferGeometry(0.5, 1, 4), material(colours.support), pyramids));
  }
  drawConnections(data.joints, false);
  drawConnections(data.supports, true);
  if (axisLines.length) {
    var axisGeometry = new THREE.BufferGeometry().setFromPoints(axisLines);
    groups.model.add(new THREE.LineSegments(axisGeometry, new THREE.LineBasicMaterial({ color: colours.axisLine })));
  }

  // ---- loads: arrows scaled to magnitude, pointing at the loaded point -----------------
  (function drawLoads() {
    var largestForce = 0, largestMoment = 0;
    data.loads.forEach(function (load) {
      largestForce = Math.max(largestForce, new THREE.Vector3().fromArray(load.force).length());
      largestMoment = Math.max(largestMoment, new THREE.Vector3().fromArray(load.moment).length());
    });
    var longest = 0.18 * size;
    var shafts = { force: [], moment: [] }, heads = { force: [], moment: [] };
    data.loads.forEach(function (load) {
      if (load.at < 0 && !load.position) return;
      var tip = load.position ? new THREE.Vector3().fromArray(load.position) : pointVector(load.at);
      [['force', load.force, largestForce], ['moment', load.moment, largestMoment]].forEach(function (item) {
        var vector = new THREE.Vector3().fromArray(item[1]);
        var magnitude = vector.length();
        if (magnitude === 0) return;
        var direction = vector.divideScalar(magnitude);
        var length = Math.max(longest * magnitude / item[2], 2.5 * markerSize);
        var tail = tip.clone().addScaledVector(direction, -length - 0.6 * markerSize);
        var end = tip.clone().addScaledVector(direction, -0.6 * markerSize);
        shafts[item[0]].push(pieceMatrix(tail, end, 0.35 * markerSize, 0.35 * markerSize));
        heads[item[0]].push(placedMatrix(end.clone().addScaledVector(direction, -0.7 * markerSize), direction, 1.1 * markerSize, 1.4 * markerSize));
        if (item[0] === 'moment')  // a double head: a moment vector
          heads.moment.push(placedMatrix(end.clone().addScaledVector(direction, -1.9 * markerSize), direction, 1.1 * markerSize, 1.4 * markerSize));
      });
    });
    var cone = new THREE.ConeBufferGeometry(0.5, 1, 12);
    ['force', 'moment'].forEach(function (what) {
      if (!shafts[what].length) return;
      var look = material(colours[what], { side: THREE.DoubleSide });
      groups.loads.add(placed(pieceGeometry, look, shafts[what]));
      groups.loads.add(placed(cone, look, heads[what]));
    });
  })();

  // ---- end effectors and their ellipsoids ----------------------------------------------
  var effectorMarkers = data.end_effectors.filter(function (e) { return e.at >= 0; }).map(function (e) {
    return placedMatrix(pointVector(e.at), null, 1.5 * markerSize, 1.5 * markerSize);
  });
  if (effectorMarkers.length)
    groups.model.add(placed(new THREE.OctahedronBufferGeometry(0.7), material(colours.effector), effectorMarkers));

  var ellipsoidKind = options.ellipsoid === 'stiffness' ? 'stiffness' : 'compliance';
  var unitSphere = new THREE.SphereBufferGeometry(1, 36, 18);
  var ellipsoidMaterial = material(colours.ellipsoid, { transparent: true, opacity: 0.38, depthWrite: false });
  // Principal values drawn as semi-axes: the largest of all end effectors is this fraction of
  // the model; an infinite stiffness (a rigidly held direction) as the largest finite one.
  function drawEllipsoids() {
    groups.ellipsoids.clear ? groups.ellipsoids.clear() : groups.ellipsoids.children.slice().forEach(function (c) { groups.ellipsoids.remove(c); });
    var largest = 0;
    data.end_effectors.forEach(function (e) {
      (e[ellipsoidKind] || []).forEach(function (value) { if (value !== null) largest = Math.max(largest, value); });
    });
    if (!(largest > 0)) return;
    var axesLines = [];
    data.end_effectors.forEach(function (e) {
      if (!e[ellipsoidKind] || e.at < 0) return;
      var semi = e[ellipsoidKind].map(function (value) {
        var drawn = value === null ? largest : value;
        return Math.max(0.15 * size * drawn / largest, 0.01 * size);
      });
      var directions = e.directions.map(function (d) { return new THREE.Vector3().fromArray(d); });
      // A right-handed basis, so that the sphere's faces keep their outside out.
      if (directions[0].clone().cross(directions[1]).dot(directions[2]) < 0) directions[2].negate();
      var position = pointVector(e.at);
      var m = new THREE.Matrix4().makeBasis(directions[0].clone().multiplyScalar(semi[0]), directions[1].clone().multiplyScalar(semi[1]),
                                            directions[2].clone().multiplyScalar(semi[2]));
      m.setPosition(position);
      var mesh = new THREE.Mesh(unitSphere, ellipsoidMaterial);
      mesh.matrixAutoUpdate = false;
      mesh.matrix.copy(m);
      groups.ellipsoids.add(mesh);
      for (var k = 0; k < 3; ++k)
        axesLines.push(position.clone().addScaledVector(directions[k], -semi[k]), position.clone().addScaledVector(directions[k], semi[k]));
    });
    groups.ellipsoids.add(new THREE.LineSegments(new THREE.BufferGeometry().setFromPoints(axesLines),
                                                 new THREE.LineBasicMaterial({ color: 0x0b5563 })));
  }

  // ---- the deformed shape --------------------------------------------------------------
  var deformed = data.deformed;
  var displacement = deformed.solved ? decode(deformed.displacement, Float32Array) : null;
  var known = deformed.solved ? decode(deformed.known, Int32Array) : null;
  var segments = deformed.segments || 1;
  var deformedMesh = null;
  var scale = deformed.solved ? deformed.scale : 0;
  if (options.scale !== undefined && isFinite(parseFloat(options.scale))) scale = Math.max(parseFloat(options.scale), 0);

  // Pieces of the deflected centre lines as thin tubes (lines are one pixel wide in WebGL), or
  // as lines where tubes would be too many triangles.
  var deformedLines = null;
  function drawDeformed() {
    if (!displacement) return;
    var count = 0;
    for (var k = 0; k < linkCount; ++k) if (known[k]) count += segments;
    var asLines = count * 12 > mostTriangles / 2;
    if (asLines && !deformedLines) {
      deformedLines = new THREE.BufferGeometry();
      deformedLines.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6 * count), 3));
      var lines = new THREE.LineSegments(deformedLines, new THREE.LineBasicMaterial({ color: colours.deformed }));
      lines.frustumCulled = false;
      groups.deformed.add(lines);
    } else if (!asLines && !deformedMesh) {
      deformedMesh = new THREE.Mesh(mergedGeometry(pieceGeometry, count), material(colours.deformed, { side: THREE.DoubleSide }));
      deformedMesh.frustumCulled = false;
      groups.deformed.add(deformedMesh);
    }
    var positions = asLines ? deformedLines.attributes.position.array : null;
    var instance = 0, pieces = [], a = new THREE.Vector3(), b = new THREE.Vector3(), start = new THREE.Vector3(), chord = new THREE.Vector3();
    for (k = 0; k < linkCount; ++k) {
      if (!known[k]) continue;
      start.copy(pointVector(ends[2 * k]));
      chord.copy(pointVector(ends[2 * k + 1])).sub(start);
      var radius = kinds[k] === 0 ? Math.max(0.3 * Math.min(sections[3 * k], sections[3 * k + 1]), 0.12 * markerSize) : 0.25 * rigidThickness;
      radius = Math.min(radius, 0.35 * markerSize);
      var base = 3 * (segments + 1) * k;
      for (var s = 0; s < segments; ++s) {
        a.copy(start).addScaledVector(chord, s / segments);
        a.x += scale * displacement[base + 3 * s]; a.y += scale * displacement[base + 3 * s + 1]; a.z += scale * displacement[base + 3 * s + 2];
        b.copy(start).addScaledVector(chord, (s + 1) / segments);
        b.x += scale * displacement[base + 3 * s + 3]; b.y += scale * displacement[base + 3 * s + 4]; b.z += scale * displacement[base + 3 * s + 5];
        if (asLines) positions.set([a.x, a.y, a.z, b.x, b.y, b.z], 6 * instance++);
        else pieces.push(pieceMatrix(a, b, 2 * radius, 2 * radius));
      }
    }
    if (asLines) deformedLines.attributes.position.needsUpdate = true;
    else fillMerged(deformedMesh.geometry, pieceGeometry, pieces);
  }

  // ---- the panel ------------------------------------------------------------------------
  document.title = data.name + ' — stiffmsa view';
  document.getElementById('title').textContent = data.name;
  document.getElementById('subtitle').textContent =
    [data.source ? 'file ' + data.source : '', data.parameters.length ? data.parameters.join(', ') : '',
     pointCount + ' points, ' + linkCount + ' links, ' + data.joints.names.length + ' joints'].filter(Boolean).join(' · ');

  var scaleNumber = document.getElementById('scale-number');
  var scaleSlider = document.getElementById('scale-slider');
  var automatic = deformed.automatic_scale || 1;
  // The slider spans the automatic factor /100 … ×100 on a logarithmic scale; its far left is 0.
  function sliderOf(value) { return value <= 0 ? 0 : Math.min(1000, Math.max(1, 500 + 250 * Math.log10(value / automatic))); }
  function valueOf(position) { return position <= 0 ? 0 : automatic * Math.pow(10, (position - 500) / 250); }
  function setScale(value, from) {
    scale = value;
    if (from !== scaleNumber) scaleNumber.value = +value.toPrecision(4);
    if (from !== scaleSlider) scaleSlider.value = sliderOf(value);
    drawDeformed();
    requestRender();
  }
  scaleNumber.addEventListener('input', function () { var v = parseFloat(scaleNumber.value); if (v >= 0) setScale(v, scaleNumber); });
  scaleSlider.addEventListener('input', function () { setScale(valueOf(+scaleSlider.value), scaleSlider); });
  var scaleNote = document.getElementById('scale-note');
  if (!deformed.solved) {
    scaleNote.textContent = 'not solved: ' + (deformed.message || 'no result');
    scaleNumber.disabled = scaleSlider.disabled = true;
  } else if (!(deformed.largest_displacement > 0)) {
    scaleNote.textContent = 'no displacement: the model has no loads';
  } else {
    scaleNote.textContent = 'automatic ×' + number(automatic) + ': the largest displacement, ' + number(deformed.largest_displacement) +
      ' m, drawn as a tenth of the model';
  }

  function bindToggle(id, object) {
    var box = document.getElementById(id);
    var apply = function () { object.visible = box.checked; requestRender(); };
    box.addEventListener('change', apply);
    apply();
  }
  bindToggle('show-deformed', groups.deformed);
  bindToggle('show-loads', groups.loads);
  bindToggle('show-ellipsoids', groups.ellipsoids);
  var showModel = document.getElementById('show-model');
  // The undeformed model turns translucent behind a deformed shape, and hides with its box.
  function applyModelLook() {
    groups.model.visible = showModel.checked;
    var ghost = groups.deformed.visible && displacement && scale > 0;
    for (var key in linkMaterials) { linkMaterials[key].opacity = ghost ? 0.3 : 1; linkMaterials[key].depthWrite = !ghost; }
    requestRender();
  }
  showModel.addEventListener('change', applyModelLook);
  document.getElementById('show-deformed').addEventListener('change', applyModelLook);
  var kindSelect = document.getElementById('ellipsoid-kind');
  kindSelect.value = ellipsoidKind;
  kindSelect.addEventListener('change', function () { ellipsoidKind = kindSelect.value; drawEllipsoids(); fillEffectors(); requestRender(); });
  var namesBox = document.getElementById('show-names');
  namesBox.checked = options.names === '1';
  namesBox.addEventListener('change', function () { buildLabels(); requestRender(); });
  document.getElementById('reset-view').addEventListener('click', function () { resetView(); requestRender(); });

  var units = { compliance: 'm/N', stiffness: 'N/m' };
  function fillEffectors() {
    var box = document.getElementById('effectors');
    box.textContent = '';
    data.end_effectors.forEach(function (e) {
      var section = element('div', undefined, 'effector');
      section.appendChild(element('b', 'end effector ' + e.name));
      if (!e.compliance) {
        section.appendChild(element('div', deformed.solved ? 'compliance not determined' : 'not solved', 'note'));
        box.appendChild(section);
        return;
      }
      section.appendChild(element('div', 'translational ' + ellipsoidKind + ' (' + units[ellipsoidKind] + '), principal values and directions', 'note'));
      var table = element('table');
      var head = element('tr');
      ['', 'value', 'x', 'y', 'z'].forEach(function (t) { head.appendChild(element('th', t)); });
      table.appendChild(head);
      for (var k = 0; k < 3; ++k) {
        var row = element('tr');
        row.appendChild(element('th', String(k + 1)));
        var value = e[ellipsoidKind][k];
        row.appendChild(element('td', value === null ? '∞ (rigid)' : number(value)));
        e.directions[k].forEach(function (c) { row.appendChild(element('td', (Math.abs(c) < 5e-4 ? 0 : c).toFixed(3))); });
        table.appendChild(row);
      }
      section.appendChild(table);
      if (e.deflection) {
        var d = e.deflection;
        section.appendChild(element('div', 'deflection under the loads: |Δp| = ' + number(Math.hypot(d[0], d[1], d[2])) + ' m, |Δφ| = ' +
                                    number(Math.hypot(d[3], d[4], d[5])) + ' rad', 'note'));
      }
      box.appendChild(section);
    });
  }

  (function fillLegend() {
    var legend = document.getElementById('legend');
    legend.appendChild(element('b', 'legend'));
    var rows = [[colours.beam, 'beam (drawn with its section)'], [colours.rigid, 'rigid link'], [colours.cad, 'CAD link (matrix or compliance)'],
                [colours.deformed, 'deformed shape (magnified by the factor above)'],
                [colours.roles[3], 'actuated joint'], [colours.roles[2], 'elastic joint'], [colours.roles[1], 'passive joint'],
                [colours.roles[0], 'rigid joint (weld)'], [colours.support, 'support (ground)'],
                [colours.force, 'force (arrow length ∝ N)'], [colours.moment, 'moment (double head, ∝ N·m)'],
                [colours.effector, 'end effector'], [colours.ellipsoid, 'ellipsoid: semi-axes ∝ principal values']];
    rows.forEach(function (row) {
      var line = element('div', undefined, 'legend-row');
      var swatch = element('span', undefined, 'swatch');
      swatch.style.background = hex(row[0]);
      line.appendChild(swatch);
      line.appendChild(document.createTextNode(row[1]));
      legend.appendChild(line);
    });
    legend.appendChild(element('div', 'joint shapes: revolute disc, prismatic bar, cylindrical rod, universal cross, spherical ball, planar plate, on their axes (black lines). Axes at the origin: x red, y green, z blue. Units SI: m, N, N·m, rad.', 'note'));
  })();

  var notes = document.getElementById('notes');
  data.notes.forEach(function (n) { notes.appendChild(element('div', n)); });
  if (!solidLinks) notes.appendChild(element('div', 'links drawn as lines: ' + linkCount + ' links are more than this page draws as solids'));

  // ---- names: labels on a toggle, a tooltip on hover -----------------------------------
  function linkMiddle(k) { return pointVector(ends[2 * k]).add(pointVector(ends[2 * k + 1])).multiplyScalar(0.5); }
  function describe(item) {
    var k = item.index;
    if (item.kind === 'point') {
      var v = pointVector(k);
      return 'point ' + data.points.names[k] + '\n(' + [v.x, v.y, v.z].map(function (c) { return number(c); }).join(', ') + ') m';
    }
    if (item.kind === 'link') {
      var length = pointVector(ends[2 * k]).distanceTo(pointVector(ends[2 * k + 1]));
      var text = 'link ' + data.links.names[k] + ' (' + data.link_kinds[kinds[k]] + ')\nfrom ' + data.points.names[ends[2 * k]] + ' to ' +
        data.points.names[ends[2 * k + 1]] + ', length ' + number(length) + ' m';
      if (kinds[k] === 0)
        text += '\nsection ' + (sections[3 * k + 2] ? '⌀ ' + number(sections[3 * k]) : number(sections[3 * k]) + ' × ' + number(sections[3 * k + 1])) + ' m';
      return text;
    }
    if (item.kind === 'joint' || item.kind === 'support') {
      var list = item.kind === 'joint' ? data.joints : data.supports;
      var axes = item.axes;
      var role = data.roles[item.role];
      var t = item.kind + ' ' + list.names[k] + ': ' + list.types[k] + ', ' + role + '\nat ' + data.points.names[item.at];
      if (axes[0] || axes[1] || axes[2]) t += '\naxis (' + axes.slice(0, 3).map(function (c) { return c.toFixed(3); }).join(', ') + ')';
      if (axes[3] || axes[4] || axes[5]) t += ', second axis (' + axes.slice(3, 6).map(function (c) { return c.toFixed(3); }).join(', ') + ')';
      return t;
    }
    var e = data.end_effectors[k];
    var s = 'end effector ' + e.name + '\nat ' + data.points.names[e.at] + (e.link ? ', link ' + e.link : '');
    if (e.compliance) s += '\nprincipal compliances ' + e.compliance.map(function (c) { return number(c); }).join(', ') + ' m/N';
    return s;
  }

  // Everything that has a name and a place, for hover and labels; links by their middle.
  var pickables = [];
  (function collect() {
    var add = function (kind, index, position, extra) {
      var item = { kind: kind, index: index, position: position };
      for (var key in extra) item[key] = extra[key];
      pickables.push(item);
    };
    data.end_effectors.forEach(function (e, k) { if (e.at >= 0) add('effector', k, pointVector(e.at)); });
    [['support', data.supports], ['joint', data.joints]].forEach(function (pair) {
      var at = decode(pair[1].at, Int32Array), role = decode(pair[1].role, Int32Array), axes = decode(pair[1].axes, Float32Array);
      for (var k = 0; k < pair[1].names.length; ++k)
        if (at[k] >= 0) add(pair[0], k, pointVector(at[k]), { at: at[k], role: role[k], axes: Array.prototype.slice.call(axes, 6 * k, 6 * k + 6) });
    });
    for (var k = 0; k < linkCount; ++k) add('link', k, linkMiddle(k));
    for (k = 0; k < pointCount; ++k) add('point', k, pointVector(k));
  })();

  var mostLabels = 300;
  var labelLayer = document.getElementById('labels');
  var labelled = [];
  var namesNote = notes.appendChild(element('div'));
  function buildLabels() {
    labelLayer.textContent = '';
    labelled = [];
    namesNote.textContent = '';
    if (!namesBox.checked) return;
    // Points are named by what stands on them, so a point with a joint is not named twice.
    var taken = {}, stopped = false;
    pickables.forEach(function (item) {
      if (labelled.length >= mostLabels) { stopped = true; return; }
      var key = item.position.toArray().join(',');
      if (item.kind === 'point' && taken[key]) return;
      taken[key] = true;
      var names = { point: data.points.names, link: data.links.names, joint: data.joints.names, support: data.supports.names };
      var text = item.kind === 'effector' ? data.end_effectors[item.index].name : names[item.kind][item.index];
      var label = element('div', text, 'label');
      labelLayer.appendChild(label);
      labelled.push({ item: item, node: label });
    });
    namesNote.textContent = stopped ? 'names shown: the first ' + labelled.length + '; hover for the others' : '';
  }
  var projected = new THREE.Vector3();
  function screenOf(position) {
    projected.copy(position).project(camera);
    return { x: (projected.x + 1) / 2 * window.innerWidth, y: (1 - projected.y) / 2 * window.innerHeight, visible: projected.z < 1 };
  }
  function placeLabels() {
    labelled.forEach(function (entry) {
      var s = screenOf(entry.item.position);
      entry.node.style.display = s.visible ? '' : 'none';
      entry.node.style.left = s.x + 'px';
      entry.node.style.top = s.y + 'px';
    });
  }

  var tooltip = document.getElementById('tooltip');
  var mouse = null;
  renderer.domElement.addEventListener('mousemove', function (event) { mouse = { x: event.clientX, y: event.clientY }; requestRender(); });
  renderer.domElement.addEventListener('mouseleave', function () { mouse = null; tooltip.hidden = true; });
  // The nearest named thing within a few pixels of the mouse: links by their whole length.
  function hover() {
    if (!mouse) return;
    var best = null, bestDistance = 10;
    pickables.forEach(function (item) {
      var distance;
      if (item.kind === 'link') {
        var a = screenOf(pointVector(ends[2 * item.index])), b = screenOf(pointVector(ends[2 * item.index + 1]));
        if (!a.visible || !b.visible) return;
        var dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
        var t = l2 > 0 ? Math.max(0, Math.min(1, ((mouse.x - a.x) * dx + (mouse.y - a.y) * dy) / l2)) : 0;
        distance = Math.hypot(a.x + t * dx - mouse.x, a.y + t * dy - mouse.y) + 3;  // ends and joints win over links
      } else {
        var s = screenOf(item.position);
        if (!s.visible) return;
        distance = Math.hypot(s.x - mouse.x, s.y - mouse.y);
      }
      if (distance < bestDistance) { bestDistance = distance; best = item; }
    });
    tooltip.hidden = !best;
    if (best) {
      tooltip.textContent = describe(best);
      tooltip.style.left = (mouse.x + 14) + 'px';
      tooltip.style.top = (mouse.y + 10) + 'px';
    }
  }

  // ---- drawing -----------------------------------------------------------------------
  var renderRequested = false;
  function render() {
    renderRequested = false;
    renderer.render(scene, camera);
    placeLabels();
    hover();
  }
  function requestRender() {
    if (renderRequested) return;
    renderRequested = true;
    requestAnimationFrame(render);
  }
  window.addEventListener('resize', function () {
    frameView();
    renderer.setSize(window.innerWidth, window.innerHeight);
    requestRender();
  });

  // Frames per second while orbiting, for bench/README.md: `frames` renders, each of a turned
  // camera, timed by requestAnimationFrame.
  window.stiffmsaMeasureFps = function (frames) {
    return new Promise(function (resolve) {
      var times = [], turn = 2 * Math.PI / frames;
      function step(time) {
        times.push(time);
        if (times.length > frames) {
          var seconds = (times[times.length - 1] - times[1]) / 1000;
          resolve({ frames: frames - 1, seconds: seconds, fps: (frames - 1) / seconds });
          return;
        }
        var offset = camera.position.clone().sub(controls.target).applyAxisAngle(new THREE.Vector3(0, 0, 1), turn);
        camera.position.copy(controls.target).add(offset);
        camera.lookAt(controls.target);
        renderer.render(scene, camera);
        requestAnimationFrame(step);
      }
      requestAnimationFrame(step);
    });
  };

  // Where a named point is drawn on the screen, for tests that move the mouse there.
  window.stiffmsaScreenOf = function (pointName) {
    var k = data.points.names.indexOf(pointName);
    return k < 0 ? null : screenOf(pointVector(k));
  };

  resetView();
  drawEllipsoids();
  fillEffectors();
  buildLabels();
  setScale(scale);
  applyModelLook();
  render();
  document.getElementById('stiffmsa-status').textContent = 'ready';
})();
