// The page of `stance view`: draws the inlined data (crates/stance-view/src, ViewData) with
// three.js, and the same data in 2-D (top view, phase plane, table). Everything it draws was
// computed by the library; this script only places it. When it is done it writes its state
// (object counts, a pixel probe, errors, load time) as JSON into #stance-status and sets
// document.body.dataset.ready, which the browser test reads.
(function () {
  'use strict';
  var status = { ready: false, webgl: false, errors: [], counts: {}, probe: null, load_ms: null };
  window.addEventListener('error', function (e) { status.errors.push(String(e.message)); publish(); });
  var consoleError = console.error;
  console.error = function () {
    status.errors.push(Array.prototype.join.call(arguments, ' '));
    consoleError.apply(console, arguments);
  };
  function publish() {
    var el = document.getElementById('stance-status');
    el.textContent = JSON.stringify(status);
  }

  var D = JSON.parse(document.getElementById('stance-data').textContent);
  var SVGNS = 'http://www.w3.org/2000/svg';
  var COLORS = {
    surface: 0xb8b4a8, contact: 0x2f6fd0, contactFaint: 0x9db6dc, pyramid: 0xd08a2f,
    polygon: 0x2e9e4f, region: 0xe07b39, robot: 0x7a7f87, joint: 0x3d4450, com: 0xd62728
  };
  function hex(c) { return '#' + ('000000' + c.toString(16)).slice(-6); }

  document.getElementById('title').textContent = D.title;
  document.getElementById('subtitle').textContent = D.subtitle;

  // ---- time and segments --------------------------------------------------------------
  var R = D.robot;
  // a simulation report: the page's time is the simulation's, the plan shown at its own time
  var S = D.simulation || null;
  var T = S ? S.t[S.t.length - 1] : (R && R.t.length ? R.t[R.t.length - 1] : 0);
  var EVENT_COLORS = { slip: 0xff7f0e, contact_loss: 0xd62728, unplanned_contact: 0x9467bd, early_touch: 0x17becf, late_lift: 0x8c564b, fall: 0x000000 };
  var current = { t: 0, frame: 0, alpha: 0 };
  var hashT = /(?:^|[#&])t=([0-9.]+)/.exec(location.hash);
  if (hashT) current.t = Math.min(T, parseFloat(hashT[1]));

  function locateIn(ts, t) {
    // frame i and weight a with t between ts[i] and ts[i + 1]
    var lo = 0, hi = ts.length - 1;
    if (t <= ts[0]) return [0, 0];
    if (t >= ts[hi]) return [hi, 0];
    while (hi - lo > 1) { var mid = (lo + hi) >> 1; if (ts[mid] <= t) lo = mid; else hi = mid; }
    return [lo, (t - ts[lo]) / (ts[lo + 1] - ts[lo])];
  }
  function locate(t) { return locateIn(R.t, t); }
  // the plan's time at the page's time (a simulation's: the plan held at its ends)
  function planTime() {
    if (!S) return current.t;
    return Math.min(Math.max(S.plan_t0 + current.t, R.t[0]), R.t[R.t.length - 1]);
  }
  function simComAt() {
    var f = locateIn(S.t, current.t), n = f[0] + 1 < S.t.length ? f[0] + 1 : f[0];
    return lerpArr(S.com[f[0]], S.com[n], f[1]);
  }
  function lerpArr(a, b, w) {
    var out = new Array(a.length);
    for (var k = 0; k < a.length; k++) out[k] = a[k] + w * (b[k] - a[k]);
    return out;
  }
  function comAt() {
    if (!R) return null;
    var i = current.frame, w = current.alpha;
    return i + 1 < R.t.length ? lerpArr(R.com[i], R.com[i + 1], w) : R.com[i];
  }
  function segmentAt() {
    if (!R) return 0;
    return R.segment[current.frame];
  }

  // ---- 2-D views ----------------------------------------------------------------------
  function el(name, attrs, parent) {
    var e = document.createElementNS(SVGNS, name);
    for (var k in attrs) e.setAttribute(k, attrs[k]);
    if (parent) parent.appendChild(e);
    return e;
  }
  var top = document.getElementById('top');
  var topMap = null, topCom = null;
  function drawTop() {
    var pts = [];
    D.stances.forEach(function (s) {
      s.contacts.forEach(function (c) { c.vertices.forEach(function (p) { pts.push(p); }); });
      if (s.polygon) s.polygon.vertices.forEach(function (p) { pts.push(p); });
    });
    if (R) R.com.forEach(function (p) { pts.push(p); });
    if (!pts.length) return;
    var x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    pts.forEach(function (p) { x0 = Math.min(x0, p[0]); x1 = Math.max(x1, p[0]); y0 = Math.min(y0, p[1]); y1 = Math.max(y1, p[1]); });
    var pad = 0.08 * Math.max(x1 - x0, y1 - y0, 0.1);
    x0 -= pad; x1 += pad; y0 -= pad; y1 += pad;
    var k = Math.min(300 / (x1 - x0), 200 / (y1 - y0));
    topMap = function (p) { return [10 + (p[0] - x0) * k, 220 - (p[1] - y0) * k]; };
    function poly(vs, attrs) {
      attrs.points = vs.map(function (p) { return topMap(p).join(','); }).join(' ');
      return el('polygon', attrs, top);
    }
    D.environment.forEach(function (s) { poly(s.vertices, { fill: '#e7e4dc', stroke: '#a9a393' }); });
    D.stances.forEach(function (s, i) {
      s.contacts.forEach(function (c) { poly(c.vertices, { fill: 'none', stroke: hex(COLORS.contact), 'stroke-width': 1, 'class': 'contact2d seg' + i }); });
      if (s.polygon && s.polygon.vertices.length > 2) {
        poly(s.polygon.vertices, { fill: hex(COLORS.polygon), 'fill-opacity': 0.25, stroke: hex(COLORS.polygon), 'class': 'poly2d seg' + i });
      }
    });
    if (R) {
      el('polyline', { points: R.com.map(function (p) { return topMap(p).join(','); }).join(' '), fill: 'none', stroke: hex(COLORS.com), 'stroke-width': 1 }, top);
      topCom = el('circle', { r: 3, fill: hex(COLORS.com) }, top);
    }
    var o = topMap([x0 + pad, y0 + pad]);
    var len = Math.pow(10, Math.floor(Math.log10(Math.max(x1 - x0, y1 - y0) / 2)));
    el('line', { x1: o[0], y1: o[1] + 12, x2: o[0] + len * k, y2: o[1] + 12, stroke: '#444' }, top);
    el('text', { x: o[0], y: o[1] + 24 }, top).textContent = len.toPrecision(1) + ' m';
  }

  var phase = document.getElementById('phase');
  var phaseMarker = null, phaseMap = null;
  function drawPhase() {
    var P = D.phase;
    if (!P || !P.s.length) return;
    document.getElementById('phasefig').hidden = false;
    // The solver caps s'^2 at its box where the whole body is at rest in path terms (costs no
    // time): clip the axis at the largest value well below the cap so the rest stays readable.
    var finite = P.x.filter(function (x) { return x < 1e6; });
    var ymax = Math.max.apply(null, finite.concat([1e-9])) * 1.1;
    var s0 = P.s[0], s1 = P.s[P.s.length - 1];
    phaseMap = function (s, x) { return [40 + (s - s0) / (s1 - s0 || 1) * 270, 180 - Math.min(x, ymax) / ymax * 165]; };
    el('line', { x1: 40, y1: 180, x2: 310, y2: 180, stroke: '#444' }, phase);
    el('line', { x1: 40, y1: 15, x2: 40, y2: 180, stroke: '#444' }, phase);
    el('text', { x: 290, y: 195 }, phase).textContent = 's';
    el('text', { x: 2, y: 12 }, phase).textContent = "s'\u00b2 (1/s\u00b2)";
    el('line', { x1: 36, y1: 15, x2: 40, y2: 15, stroke: '#444' }, phase);
    el('text', { x: 44, y: 18 }, phase).textContent = ymax.toPrecision(2);
    el('text', { x: 30, y: 195 }, phase).textContent = '0';
    var starts = P.segment_starts;
    for (var g = 0; g + 1 < starts.length; g++) {
      var pts = [];
      for (var i = starts[g]; i <= starts[g + 1] && i < P.s.length; i++) pts.push(phaseMap(P.s[i], P.x[i]).join(','));
      el('polyline', { points: pts.join(' '), fill: 'none', stroke: g % 2 ? '#1f77b4' : '#ff7f0e', 'stroke-width': 1.5 }, phase);
      var a = phaseMap(P.s[starts[g]], 0);
      el('line', { x1: a[0], y1: 15, x2: a[0], y2: 180, stroke: '#ccc', 'stroke-dasharray': '2,2' }, phase);
    }
    phaseMarker = el('line', { x1: 40, y1: 15, x2: 40, y2: 180, stroke: hex(COLORS.com) }, phase);
  }
  function sAt(t) {
    var P = D.phase;
    if (!P || !P.t.length) return null;
    var i = 0;
    while (i + 1 < P.t.length && P.t[i + 1] <= t) i++;
    if (i + 1 >= P.t.length) return P.s[P.s.length - 1];
    var w = (t - P.t[i]) / (P.t[i + 1] - P.t[i] || 1);
    return P.s[i] + w * (P.s[i + 1] - P.s[i]);
  }

  function drawTable() {
    var t = document.getElementById('table');
    var head = document.createElement('tr');
    D.table.columns.forEach(function (c) { var th = document.createElement('th'); th.textContent = c; head.appendChild(th); });
    t.appendChild(head);
    D.table.rows.forEach(function (r) {
      var tr = document.createElement('tr');
      r.forEach(function (c) { var td = document.createElement('td'); td.textContent = c; tr.appendChild(td); });
      t.appendChild(tr);
    });
    var notes = document.getElementById('notes');
    D.notes.forEach(function (n) { var li = document.createElement('li'); li.textContent = n; notes.appendChild(li); });
  }

  // ---- 3-D ----------------------------------------------------------------------------
  var three = null;
  function webglAvailable() {
    try {
      var c = document.createElement('canvas');
      return !!(window.WebGL2RenderingContext && c.getContext('webgl2')) || !!c.getContext('webgl');
    } catch (e) { return false; }
  }

  function fan(vertices, z) {
    // triangle fan of a convex polygon (world points), as a BufferGeometry
    var pos = [];
    for (var i = 1; i + 1 < vertices.length; i++) {
      [vertices[0], vertices[i], vertices[i + 1]].forEach(function (p) { pos.push(p[0], p[1], z === undefined ? p[2] : z); });
    }
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    g.computeVertexNormals();
    return g;
  }
  function loop(vertices, z) {
    var pos = [];
    for (var i = 0; i < vertices.length; i++) {
      var a = vertices[i], b = vertices[(i + 1) % vertices.length];
      pos.push(a[0], a[1], z === undefined ? a[2] : z, b[0], b[1], z === undefined ? b[2] : z);
    }
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    return g;
  }
  function segments(pos, color, opacity) {
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    return new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: color, transparent: opacity < 1, opacity: opacity }));
  }
  function label(text, at, size) {
    var c = document.createElement('canvas');
    c.width = 256; c.height = 64;
    var x = c.getContext('2d');
    x.font = '36px sans-serif'; x.fillStyle = '#333'; x.fillText(text, 4, 44);
    var s = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(c), depthTest: false }));
    s.position.set(at[0], at[1], at[2]);
    s.scale.set(size * 4, size, 1);
    return s;
  }

  // the bytes of a base64 string (the packed meshes: crates/stance-view/src/meshes)
  function bytes(b64) {
    var s = atob(b64), a = new Uint8Array(s.length);
    for (var i = 0; i < s.length; i++) a[i] = s.charCodeAt(i);
    return a.buffer;
  }
  // a URDF shape in its own frame (three.js's cylinders and capsules run along y, URDF's along z)
  function shapeGeometry(shape, meshGeometries) {
    switch (shape.kind) {
      case 'mesh': return meshGeometries[shape.data];
      case 'box': return new THREE.BoxGeometry(shape.size[0], shape.size[1], shape.size[2]);
      case 'cylinder': return new THREE.CylinderGeometry(shape.radius, shape.radius, shape.length, 24).rotateX(Math.PI / 2);
      case 'capsule': return new THREE.CapsuleGeometry(shape.radius, shape.length, 4, 16).rotateX(Math.PI / 2);
      default: return new THREE.SphereGeometry(shape.radius, 20, 14);
    }
  }

  // friction usage |f_t| / (mu f_n) to a colour: green (0) to yellow (0.5) to red (1);
  // magenta beyond 1 (the force would slide under Coulomb's law)
  function usageColor(u) {
    if (u > 1) return 0xc000c0;
    var r = Math.round(255 * Math.min(1, 2 * u)), g = Math.round(200 * Math.min(1, 2 * (1 - u)));
    return (r << 16) | (g << 8);
  }

  function build3d() {
    // the camera frames what matters (contacts, robot, polygons, region), not the whole floor
    var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    function grow(p) { for (var k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], p[k]); hi[k] = Math.max(hi[k], p[k]); } }
    D.stances.forEach(function (s) { s.contacts.forEach(function (c) { c.vertices.forEach(grow); }); });
    if (R) R.positions.forEach(function (f) { for (var j = 0; j < f.length; j += 3) grow([f[j], f[j + 1], f[j + 2]]); });
    if (D.region) D.region.vertices.forEach(grow);
    D.stances.forEach(function (s) { if (s.polygon) s.polygon.vertices.forEach(function (v) { grow([v[0], v[1], s.polygon.height]); }); });
    if (!isFinite(lo[0])) D.environment.forEach(function (s) { s.vertices.forEach(grow); });
    var h = D.scale;
    var floorZ = lo[2];
    D.environment.forEach(function (s) { s.vertices.forEach(function (p) { floorZ = Math.min(floorZ, p[2]); }); });

    var container = document.getElementById('three');
    var renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setSize(container.clientWidth, container.clientHeight);
    renderer.setClearColor(0xf4f6f8);
    container.appendChild(renderer.domElement);
    var scene = new THREE.Scene();
    var camera = new THREE.PerspectiveCamera(40, container.clientWidth / container.clientHeight, 0.01, 1000);
    camera.up.set(0, 0, 1);
    scene.add(new THREE.HemisphereLight(0xffffff, 0x888877, 2.0));
    var sun = new THREE.DirectionalLight(0xffffff, 1.5);
    sun.position.set(2, -3, 5);
    scene.add(sun);

    var layers = {};
    function layer(name, title, on) {
      var g = new THREE.Group();
      g.name = name;
      scene.add(g);
      layers[name] = { group: g, title: title, on: on };
      g.visible = on;
      return g;
    }
    var gAxes = layer('axes', 'axes and grid', true);
    var gEnv = D.environment.length ? layer('environment', 'environment', true) : null;
    var gContacts = layer('contacts', 'contacts', true);
    var gFrames = layer('frames', 'contact frames', true);
    var gPyr = layer('pyramids', 'friction pyramids', true);
    var gPoly = layer('polygon', 'static polygon', true);
    var gPrism = layer('prism', 'polygon prism', false);
    var gRegion = D.region ? layer('region', 'robust region M', true) : null;
    var hasMeshes = !!(R && R.meshes && R.meshes.length);
    var gRobot = R ? layer('robot', hasMeshes ? 'robot' : 'robot (capsules)', true) : null;
    var gBones = hasMeshes ? layer('links', 'links as capsules', false) : gRobot;
    var gCom = R ? layer('com', 'CoM and path', true) : null;
    var gForces = D.forces ? layer('forces', 'contact forces', true) : null;
    var gClear = D.clearance ? layer('clearance', 'closest approaches', true) : null;

    // axes and grid (1 line every grid step, on the lowest plane)
    var span = Math.max(hi[0] - lo[0], hi[1] - lo[1], 0.5);
    var step = Math.pow(10, Math.floor(Math.log10(span / 2)));
    var gridPos = [];
    var gx0 = Math.floor((lo[0] - span * 0.2) / step) * step, gx1 = Math.ceil((hi[0] + span * 0.2) / step) * step;
    var gy0 = Math.floor((lo[1] - span * 0.2) / step) * step, gy1 = Math.ceil((hi[1] + span * 0.2) / step) * step;
    for (var gx = gx0; gx <= gx1 + 1e-9; gx += step) gridPos.push(gx, gy0, floorZ, gx, gy1, floorZ);
    for (var gy = gy0; gy <= gy1 + 1e-9; gy += step) gridPos.push(gx0, gy, floorZ, gx1, gy, floorZ);
    gAxes.add(segments(gridPos, 0xcfd3d8, 1));
    var al = 2 * h, ls = Math.max(0.5 * h, 0.03 * span);
    gAxes.add(segments([0, 0, 0, al, 0, 0], 0xd62728, 1));
    gAxes.add(segments([0, 0, 0, 0, al, 0], 0x2ca02c, 1));
    gAxes.add(segments([0, 0, 0, 0, 0, al], 0x1f77b4, 1));
    gAxes.add(label('x (m)', [al * 1.15, 0, 0], ls));
    gAxes.add(label('y (m)', [0, al * 1.15, 0], ls));
    gAxes.add(label('z (m)', [0, 0, al * 1.15], ls));
    gAxes.add(label('grid ' + step + ' m', [gx1, gy0, floorZ], ls));

    D.environment.forEach(function (s) {
      gEnv.add(new THREE.Mesh(fan(s.vertices), new THREE.MeshStandardMaterial({ color: COLORS.surface, side: THREE.DoubleSide, transparent: true, opacity: 0.85, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 })));
      gEnv.add(new THREE.LineSegments(loop(s.vertices), new THREE.LineBasicMaterial({ color: 0x8a8579 })));
    });

    var stanceGroups = [];
    var counts = { surfaces: D.environment.length, contacts: 0, pyramids: 0, pyramid_edges: 0, polygons: 0, region_faces: 0, bones: 0, stances: D.stances.length };
    D.stances.forEach(function (s) {
      var sg = { contacts: new THREE.Group(), frames: new THREE.Group(), pyramids: new THREE.Group(), polygon: null, prism: null, materials: [] };
      gContacts.add(sg.contacts); gFrames.add(sg.frames); gPyr.add(sg.pyramids);
      s.contacts.forEach(function (c) {
        var m = new THREE.MeshStandardMaterial({ color: COLORS.contact, side: THREE.DoubleSide, polygonOffset: true, polygonOffsetFactor: -1, polygonOffsetUnits: -1 });
        sg.materials.push(m);
        var mesh = new THREE.Mesh(fan(c.vertices), m);
        mesh.userData.contact = c.name;
        sg.contacts.add(mesh);
        sg.contacts.add(new THREE.LineSegments(loop(c.vertices), new THREE.LineBasicMaterial({ color: 0x1b3f7a })));
        counts.contacts++;
        var p = c.position, a = c.axes, f = 0.8 * h;
        sg.frames.add(segments([p[0], p[1], p[2], p[0] + f * a[0][0], p[1] + f * a[1][0], p[2] + f * a[2][0]], 0xd62728, 1));
        sg.frames.add(segments([p[0], p[1], p[2], p[0] + f * a[0][1], p[1] + f * a[1][1], p[2] + f * a[2][1]], 0x2ca02c, 1));
        sg.frames.add(segments([p[0], p[1], p[2], p[0] + f * a[0][2], p[1] + f * a[1][2], p[2] + f * a[2][2]], 0x1f77b4, 1));
        c.vertices.forEach(function (v) {
          var pos = [];
          var tips = c.edges.map(function (e) { return [v[0] + h * e[0], v[1] + h * e[1], v[2] + h * e[2]]; });
          tips.forEach(function (t, i) {
            var u = tips[(i + 1) % tips.length];
            pos.push(v[0], v[1], v[2], t[0], t[1], t[2], t[0], t[1], t[2], u[0], u[1], u[2]);
          });
          sg.pyramids.add(segments(pos, COLORS.pyramid, 0.9));
          counts.pyramids++;
          counts.pyramid_edges += tips.length;
        });
      });
      if (s.polygon && s.polygon.vertices.length > 2) {
        var pv = s.polygon.vertices;
        sg.polygon = new THREE.Group();
        sg.polygon.add(new THREE.Mesh(fan(pv.map(function (v) { return [v[0], v[1], 0]; })), new THREE.MeshBasicMaterial({ color: COLORS.polygon, transparent: true, opacity: 0.35, side: THREE.DoubleSide, depthWrite: false })));
        sg.polygon.add(new THREE.LineSegments(loop(pv.map(function (v) { return [v[0], v[1], 0]; })), new THREE.LineBasicMaterial({ color: COLORS.polygon })));
        sg.polygon.position.z = s.polygon.height;
        gPoly.add(sg.polygon);
        counts.polygons++;
        // the prism: the polygon swept along gravity down to the lowest contact
        var g = D.gravity, depth = s.polygon.height - floorZ;
        var sx = g[2] !== 0 ? g[0] / -g[2] : 0, sy = g[2] !== 0 ? g[1] / -g[2] : 0;
        var walls = [];
        var bottom = pv.map(function (v) { return [v[0] + sx * depth, v[1] + sy * depth, floorZ]; });
        var topv = pv.map(function (v) { return [v[0], v[1], s.polygon.height]; });
        for (var i = 0; i < pv.length; i++) {
          var j = (i + 1) % pv.length;
          [topv[i], bottom[i], bottom[j], topv[i], bottom[j], topv[j]].forEach(function (p) { walls.push(p[0], p[1], p[2]); });
        }
        var wg = new THREE.BufferGeometry();
        wg.setAttribute('position', new THREE.Float32BufferAttribute(walls, 3));
        sg.prism = new THREE.Mesh(wg, new THREE.MeshBasicMaterial({ color: COLORS.polygon, transparent: true, opacity: 0.12, side: THREE.DoubleSide, depthWrite: false }));
        gPrism.add(sg.prism);
      }
      stanceGroups.push(sg);
    });

    if (gRegion && D.region.vertices.length) {
      var rv = D.region.vertices, tri = [];
      D.region.faces.forEach(function (f) {
        for (var i = 1; i + 1 < f.length; i++) [f[0], f[i], f[i + 1]].forEach(function (k) { tri.push(rv[k][0], rv[k][1], rv[k][2]); });
        counts.region_faces++;
      });
      var rg = new THREE.BufferGeometry();
      rg.setAttribute('position', new THREE.Float32BufferAttribute(tri, 3));
      rg.computeVertexNormals();
      gRegion.add(new THREE.Mesh(rg, new THREE.MeshStandardMaterial({ color: COLORS.region, transparent: true, opacity: 0.35, side: THREE.DoubleSide, depthWrite: false })));
      var edges = [];
      D.region.faces.forEach(function (f) {
        for (var i = 0; i < f.length; i++) { var a = rv[f[i]], b = rv[f[(i + 1) % f.length]]; edges.push(a[0], a[1], a[2], b[0], b[1], b[2]); }
      });
      gRegion.add(segments(edges, 0xa04f1c, 0.8));
    }

    // the robots: the plan's (a translucent ghost beside a simulation), and the simulation's
    var meshGeometries = hasMeshes ? R.mesh_data.map(function (d) {
      var g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(new Float32Array(bytes(d.positions)), 3));
      var ib = bytes(d.indices);
      g.setIndex(Array.from(d.index_bytes === 2 ? new Uint16Array(ib) : new Uint32Array(ib)));
      return g;
    }) : [];
    var planRobot = null, simRobot = null, gSim = null;
    counts.meshes = 0;
    counts.robots = 0;
    if (R) {
      planRobot = makeRobot(hasMeshes ? gRobot : null, gBones, S ? 0.3 : 1);
      counts.meshes = planRobot.meshes;
      counts.bones = R.bones.length;
    }
    if (S) {
      gSim = layer('executed', 'executed in MuJoCo', true);
      simRobot = makeRobot(hasMeshes ? gSim : null, hasMeshes ? null : gSim, 1);
      counts.executed_meshes = simRobot.meshes;
    }
    var mainRobot = simRobot || planRobot, mainGroup = S ? gSim : gRobot;

    // a robot: the URDF's geometries, each on its joint's frame (meshGroup), and capsules
    // between joint origins (boneGroup); placed from a frame's joint positions and orientations
    function makeRobot(meshGroup, boneGroup, opacity) {
      var robot = { frames: {}, bones: [], balls: [], meshes: 0 };
      counts.robots++;
      if (meshGroup) {
        R.meshes.forEach(function (mv) {
          var frame = robot.frames[mv.joint];
          if (!frame) { frame = robot.frames[mv.joint] = new THREE.Group(); meshGroup.add(frame); }
          var alpha = mv.color[3] * opacity;
          var m = new THREE.Mesh(shapeGeometry(mv.shape, meshGeometries), new THREE.MeshStandardMaterial({
            color: new THREE.Color().setRGB(mv.color[0], mv.color[1], mv.color[2], 'srgb'),
            flatShading: true, roughness: 0.75, metalness: 0.05,
            transparent: alpha < 1, opacity: alpha, depthWrite: alpha >= 1
          }));
          var o = mv.origin;
          m.position.set(o[0], o[1], o[2]);
          m.quaternion.set(o[3], o[4], o[5], o[6]);
          if (mv.shape.kind === 'mesh') m.scale.set(mv.shape.scale[0], mv.shape.scale[1], mv.shape.scale[2]);
          m.userData.link = mv.link;
          frame.add(m);
          robot.meshes++;
        });
      }
      if (boneGroup) {
        var cyl = new THREE.CylinderGeometry(R.radius, R.radius, 1, 12);
        var ball = new THREE.SphereGeometry(R.radius * 1.15, 12, 8);
        var mb = new THREE.MeshStandardMaterial({ color: COLORS.robot, roughness: 0.6, transparent: opacity < 1, opacity: opacity });
        var mj = new THREE.MeshStandardMaterial({ color: COLORS.joint, roughness: 0.6, transparent: opacity < 1, opacity: opacity });
        R.bones.forEach(function () { var m = new THREE.Mesh(cyl, mb); boneGroup.add(m); robot.bones.push(m); });
        var used = {};
        R.bones.forEach(function (b) { used[b[0]] = true; used[b[1]] = true; });
        Object.keys(used).forEach(function (j) { var m = new THREE.Mesh(ball, mj); m.userData.joint = +j; boneGroup.add(m); robot.balls.push(m); });
      }
      // P: joint positions (3 per joint); O, O1: orientations (4 per joint) at the frames
      // around the time, w the weight of O1
      robot.place = function (P, O, O1, w) {
        function at(j) { return new THREE.Vector3(P[3 * j], P[3 * j + 1], P[3 * j + 2]); }
        R.bones.forEach(function (b, k) {
          var a = at(b[0]), e = at(b[1]);
          var d = e.clone().sub(a), len = d.length();
          var m = robot.bones[k];
          if (!m) return;
          m.position.copy(a).add(e).multiplyScalar(0.5);
          m.scale.set(1, Math.max(len, 1e-6), 1);
          if (len > 0) m.quaternion.setFromUnitVectors(up, d.divideScalar(len));
        });
        robot.balls.forEach(function (m) { m.position.copy(at(m.userData.joint)); });
        Object.keys(robot.frames).forEach(function (k) {
          var j = +k, g = robot.frames[k];
          g.position.copy(at(j));
          qa.set(O[4 * j], O[4 * j + 1], O[4 * j + 2], O[4 * j + 3]);
          qb.set(O1[4 * j], O1[4 * j + 1], O1[4 * j + 2], O1[4 * j + 3]);
          g.quaternion.copy(qa).slerp(qb, w);
        });
      };
      return robot;
    }

    // the simulation's events: a numbered marker where each happened
    var eventMarkers = [];
    if (S) {
      var gEvents = layer('events', 'simulation events', true);
      S.events.forEach(function (e) {
        var g = new THREE.Group();
        var ball = new THREE.Mesh(new THREE.SphereGeometry(0.025, 16, 12), new THREE.MeshBasicMaterial({ color: EVENT_COLORS[e.kind] || 0x000000, depthTest: false }));
        ball.renderOrder = 11;
        g.add(ball);
        var tag = label(String(e.number), [0.05, 0, 0.05], 0.06);
        g.add(tag);
        g.position.set(e.position[0], e.position[1], e.position[2]);
        g.userData.event = e;
        gEvents.add(g);
        eventMarkers.push(g);
      });
      counts.events = eventMarkers.length;
    }
    var comBall = null, comLine = null;
    if (R) {
      comBall = new THREE.Mesh(new THREE.SphereGeometry(0.3 * h, 16, 12), new THREE.MeshStandardMaterial({ color: COLORS.com }));
      gCom.add(comBall);
      var cp = [];
      for (var i = 0; i + 1 < R.com.length; i++) cp.push.apply(cp, R.com[i].concat(R.com[i + 1]));
      gCom.add(segments(cp, COLORS.com, 0.8));
      comLine = segments([0, 0, 0, 0, 0, 0], COLORS.com, 0.5);
      gCom.add(comLine);
    }

    // contact forces: an arrow per contact vertex, from the vertex along the force on the robot
    // (WEIGHT_ARROW per weight), coloured by friction usage against Coulomb's circle
    var arrows = [];
    if (gForces) {
      var most = 0;
      D.stances.forEach(function (st) { var n = 0; st.contacts.forEach(function (c) { n += c.vertices.length; }); most = Math.max(most, n); });
      for (var ai = 0; ai < most; ai++) {
        var arrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 0.1, 0x2e9e4f);
        arrow.visible = false;
        // drawn over the robot: the forces act under its feet and hands
        arrow.line.material.depthTest = false; arrow.cone.material.depthTest = false;
        arrow.renderOrder = 10;
        gForces.add(arrow);
        arrows.push(arrow);
      }
    }
    // closest approaches: a segment from the body's closest point to the solid's
    var nearLines = gClear ? segments(new Array(6 * 64).fill(0), 0xd62728, 1) : null;
    if (nearLines) { nearLines.material.linewidth = 2; gClear.add(nearLines); }

    // camera: the whole scene (a motion: the robot where it is now), from the front-right, a
    // little above
    var c = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2];
    var radius = 0.5 * Math.sqrt(Math.pow(hi[0] - lo[0], 2) + Math.pow(hi[1] - lo[1], 2) + Math.pow(hi[2] - lo[2], 2)) || 1;
    var controls = new THREE.OrbitControls(camera, renderer.domElement);
    function aim(c, radius) {
      var dist = 1.15 * radius / Math.sin((camera.fov / 2) * Math.PI / 180);
      var dir = new THREE.Vector3(0.75, -1.0, 0.55).normalize();
      camera.position.set(c[0] + dist * dir.x, c[1] + dist * dir.y, c[2] + dist * dir.z);
      camera.near = dist / 100; camera.far = dist * 10; camera.updateProjectionMatrix();
      controls.target.set(c[0], c[1], c[2]);
      controls.update();
    }
    aim(c, radius);
    controls.addEventListener('change', function () { render(); });
    // following the robot: the camera and its target move with the CoM's horizontal motion
    var followed = null, followBox = document.getElementById('follow');
    function follow(p) {
      if (!followBox || !followBox.checked) { followed = null; return; }
      var v = new THREE.Vector3(p[0], p[1], 0);
      if (followed) {
        var d = v.clone().sub(followed);
        camera.position.add(d); controls.target.add(d); controls.update();
      }
      followed = v;
    }

    var up = new THREE.Vector3(0, 1, 0);
    var qa = new THREE.Quaternion(), qb = new THREE.Quaternion();
    function pose() {
      var seg = segmentAt();
      stanceGroups.forEach(function (sg, i) {
        var on = D.kind === 'scene' || i === seg;
        sg.materials.forEach(function (m) { m.color.setHex(on ? COLORS.contact : COLORS.contactFaint); });
        sg.pyramids.visible = on;
        sg.frames.visible = on;
        if (sg.polygon) sg.polygon.visible = on;
        if (sg.prism) sg.prism.visible = on;
      });
      if (!R) return;
      var i = current.frame, w = current.alpha, n1 = i + 1 < R.t.length ? i + 1 : i;
      planRobot.place(lerpArr(R.positions[i], R.positions[n1], w), R.orientations[i], R.orientations[n1], w);
      if (S) {
        var si = locateIn(S.t, current.t), sn = si[0] + 1 < S.t.length ? si[0] + 1 : si[0];
        simRobot.place(lerpArr(S.positions[si[0]], S.positions[sn], si[1]), S.orientations[si[0]], S.orientations[sn], si[1]);
        eventMarkers.forEach(function (g) {
          // an event's marker grows while it happens (within 0.1 s)
          var k = Math.abs(g.userData.event.t - current.t) < 0.1 ? 2 : 1;
          g.scale.set(k, k, k);
        });
      }
      var com = comAt();
      follow(S ? simComAt() : com);
      comBall.position.set(com[0], com[1], com[2]);
      var cl = comLine.geometry.attributes.position;
      cl.setXYZ(0, com[0], com[1], com[2]);
      cl.setXYZ(1, com[0], com[1], floorZ);
      cl.needsUpdate = true;
      var st = D.stances[seg];
      if (gForces) {
        var F = D.forces, fi = current.frame, used = 0, dirv = new THREE.Vector3();
        // the frame's forces, held until the next frame (they change with the stance)
        if (F.feasible[fi] && st) {
          st.contacts.forEach(function (c, ci) {
            c.vertices.forEach(function (v, vi) {
              var f = F.forces[fi][ci][vi], a = arrows[used++];
              var len = Math.sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) * F.scale;
              if (len < 1e-4) { a.visible = false; return; }
              a.visible = true;
              a.position.set(v[0], v[1], v[2]);
              a.setDirection(dirv.set(f[0], f[1], f[2]).normalize());
              a.setLength(len, Math.min(0.3 * len, 0.04), Math.min(0.15 * len, 0.02));
              a.setColor(usageColor(F.usage[fi][ci][vi]));
            });
          });
        }
        for (var k = used; k < arrows.length; k++) arrows[k].visible = false;
      }
      if (nearLines) {
        var near = D.clearance.frames[current.frame] || [], np = nearLines.geometry.attributes.position;
        for (var n = 0; n < 64; n++) {
          var e = near[n];
          if (e) {
            var d = Math.max(e.distance, 0);
            np.setXYZ(2 * n, e.point[0], e.point[1], e.point[2]);
            np.setXYZ(2 * n + 1, e.point[0] + d * e.normal[0], e.point[1] + d * e.normal[1], e.point[2] + d * e.normal[2]);
          } else { np.setXYZ(2 * n, 0, 0, 0); np.setXYZ(2 * n + 1, 0, 0, 0); }
        }
        np.needsUpdate = true;
      }
      if (st && stanceGroups[seg].polygon && Math.abs(D.gravity[0]) + Math.abs(D.gravity[1]) === 0) {
        stanceGroups[seg].polygon.position.z = com[2];
      }
    }
    function render() { renderer.render(scene, camera); }

    // layer toggles
    var box2 = document.getElementById('layers');
    Object.keys(layers).forEach(function (name) {
      var L = layers[name];
      var lab = document.createElement('label');
      var cb = document.createElement('input');
      cb.type = 'checkbox'; cb.checked = L.on; cb.dataset.layer = name;
      cb.addEventListener('change', function () { L.group.visible = cb.checked; render(); });
      lab.appendChild(cb);
      lab.appendChild(document.createTextNode(' ' + L.title));
      box2.appendChild(lab);
    });
    var legend = document.getElementById('legend');
    [['contacts', COLORS.contact], ['friction pyramids', COLORS.pyramid], ['static polygon', COLORS.polygon]]
      .concat(D.region ? [['robust region M', COLORS.region]] : [])
      .concat(R ? [['CoM', COLORS.com]] : [])
      .concat(D.forces ? [['force, friction usage 0', usageColor(0)], ['0.5', usageColor(0.5)], ['1', usageColor(1)], ['> 1', usageColor(1.5)]] : [])
      .concat(D.clearance ? [['closest approach < ' + (D.clearance.threshold * 100) + ' cm', 0xd62728]] : [])
      .forEach(function (x) {
        var s = document.createElement('span'); s.style.background = hex(x[1]);
        legend.appendChild(s); legend.appendChild(document.createTextNode(x[0]));
      });
    window.addEventListener('resize', function () {
      camera.aspect = container.clientWidth / container.clientHeight;
      camera.updateProjectionMatrix();
      renderer.setSize(container.clientWidth, container.clientHeight);
      render();
    });
    // a motion: the camera frames the robot where it is at the start (its drawn geometry's
    // bounding spheres, or its joints), with room for the contacts around it
    if (R) {
      var fa = locate(planTime());
      current.frame = fa[0]; current.alpha = fa[1];
      pose();
      scene.updateMatrixWorld(true);
      var blo = [Infinity, Infinity, Infinity], bhi = [-Infinity, -Infinity, -Infinity];
      function box(p, r) { for (var k = 0; k < 3; k++) { blo[k] = Math.min(blo[k], p[k] - r); bhi[k] = Math.max(bhi[k], p[k] + r); } }
      Object.keys(mainRobot.frames).forEach(function (k) {
        mainRobot.frames[k].children.forEach(function (m) {
          m.geometry.computeBoundingSphere();
          var bs = m.geometry.boundingSphere, cw = bs.center.clone().applyMatrix4(m.matrixWorld);
          box([cw.x, cw.y, cw.z], bs.radius * Math.max(m.scale.x, m.scale.y, m.scale.z));
        });
      });
      var P0 = S ? S.positions[locateIn(S.t, current.t)[0]] : R.positions[current.frame];
      for (var j3 = 0; j3 < P0.length; j3 += 3) box([P0[j3], P0[j3 + 1], P0[j3 + 2]], R.radius);
      var half = 0.5 * Math.sqrt(Math.pow(bhi[0] - blo[0], 2) + Math.pow(bhi[1] - blo[1], 2) + Math.pow(bhi[2] - blo[2], 2));
      aim([(blo[0] + bhi[0]) / 2, (blo[1] + bhi[1]) / 2, (blo[2] + bhi[2]) / 2], 0.75 * half);
    }
    function probeLink(link) {
      var target = null, swapped = [];
      Object.keys(mainRobot.frames).forEach(function (k) {
        mainRobot.frames[k].children.forEach(function (m) {
          if (!target && m.userData.link === link) target = m;
          swapped.push([m, m.material]);
          m.material = new THREE.MeshBasicMaterial({ color: m.material.color });
        });
      });
      if (!target) { swapped.forEach(function (x) { x[0].material = x[1]; }); return { link: link, error: 'no mesh of that link' }; }
      var shown = [];
      scene.children.forEach(function (g) { if (g.isGroup) { shown.push([g, g.visible]); g.visible = g === mainGroup; } });
      scene.updateMatrixWorld(true);
      target.geometry.computeBoundingSphere();
      var q = target.geometry.boundingSphere.center.clone().applyMatrix4(target.matrixWorld).project(camera);
      render();
      var gl = renderer.getContext();
      var px = Math.round((q.x + 1) / 2 * (gl.drawingBufferWidth - 1)), py = Math.round((q.y + 1) / 2 * (gl.drawingBufferHeight - 1));
      var rgba = new Uint8Array(4);
      gl.readPixels(px, py, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, rgba);
      shown.forEach(function (x) { x[0].visible = x[1]; });
      swapped.forEach(function (x) { x[0].material.dispose(); x[0].material = x[1]; });
      render();
      return { link: link, pixel: [px, py], rgba: Array.from(rgba), color: '#' + target.material.color.getHexString('srgb') };
    }
    return { probeLink: probeLink, pose: pose, render: render, renderer: renderer, camera: camera, scene: scene, counts: counts, stanceGroups: stanceGroups };
  }

  // ---- time updates -------------------------------------------------------------------
  var clock = document.getElementById('clock');
  var slider = document.getElementById('time');
  function update() {
    if (R) {
      var fa = locate(planTime());
      current.frame = fa[0]; current.alpha = fa[1];
      clock.textContent = 't = ' + current.t.toFixed(3) + ' s of ' + T.toFixed(3) + ' s' +
        (S ? ' simulated (plan at ' + planTime().toFixed(3) + ' s)' : '') + ', segment ' + D.stances[segmentAt()].name;
      document.querySelectorAll('#timeline .mark, #events li').forEach(function (m) {
        m.classList.toggle('now', Math.abs(parseFloat(m.dataset.t) - current.t) < 0.1);
      });
      document.getElementById('margins').textContent = margins(current.frame);
      slider.value = String(T > 0 ? current.t / T : 0);
      var rows = document.querySelectorAll('#table tr');
      for (var i = 1; i < rows.length; i++) rows[i].className = i - 1 === segmentAt() ? 'current' : '';
      if (topCom) { var p = topMap(comAt()); topCom.setAttribute('cx', p[0]); topCom.setAttribute('cy', p[1]); }
      var s = sAt(planTime());
      if (phaseMarker && s !== null) { var x = phaseMap(s, 0)[0]; phaseMarker.setAttribute('x1', x); phaseMarker.setAttribute('x2', x); }
      var seg = segmentAt();
      document.querySelectorAll('.contact2d, .poly2d').forEach(function (e) {
        e.style.display = e.classList.contains('seg' + seg) ? '' : (e.classList.contains('poly2d') ? 'none' : '');
        e.style.opacity = e.classList.contains('seg' + seg) ? 1 : 0.3;
      });
    }
    if (three) { three.pose(); three.render(); }
  }
  // one line per margin at a frame: friction usage, closest approach, worst torque ratio
  function margins(fi) {
    var out = [];
    if (D.forces) {
      if (!D.forces.feasible[fi]) out.push('no contact forces hold this frame');
      else {
        // at the vertices, and of each contact's resultant (its axes: x, y, normal)
        var u = 0, ur = 0, st = D.stances[R.segment[fi]];
        D.forces.usage[fi].forEach(function (c) { c.forEach(function (x) { u = Math.max(u, x); }); });
        D.forces.forces[fi].forEach(function (fs, ci) {
          var F = [0, 0, 0], a = st.contacts[ci].axes;
          fs.forEach(function (f) { F[0] += f[0]; F[1] += f[1]; F[2] += f[2]; });
          var loc = [0, 1, 2].map(function (k) { return a[0][k] * F[0] + a[1][k] * F[1] + a[2][k] * F[2]; });
          if (loc[2] > 1e-9) ur = Math.max(ur, Math.sqrt(loc[0] * loc[0] + loc[1] * loc[1]) / (st.contacts[ci].friction * loc[2]));
        });
        out.push('friction usage (Coulomb): vertices ' + u.toFixed(2) + (u > 1 ? ' (> 1: a corner of the pyramid)' : '') + ', contacts ' + ur.toFixed(2));
      }
    }
    if (D.clearance) {
      var near = D.clearance.frames[fi];
      if (near.length) {
        var c = near.reduce(function (a, b) { return b.distance < a.distance ? b : a; });
        out.push('closest: ' + c.body + ' to ' + c.surface + ', ' + (c.distance * 1000).toFixed(1) + ' mm');
      }
    }
    if (D.torque && D.torque.balanced[fi]) out.push('worst torque: ' + D.torque.joint[fi] + ' at ' + D.torque.ratio[fi].toFixed(2) + ' of its limit');
    return out.join('\n');
  }

  var playing = false, last = null;
  function tick(now) {
    if (!playing) return;
    if (last !== null) {
      current.t += (now - last) / 1000 * parseFloat(document.getElementById('speed').value);
      if (current.t > T) current.t = 0;
    }
    last = now;
    update();
    requestAnimationFrame(tick);
  }
  if (R) {
    document.getElementById('playback').hidden = false;
    var play = document.getElementById('play');
    play.addEventListener('click', function () {
      playing = !playing; last = null;
      play.textContent = playing ? 'Pause' : 'Play';
      if (playing) requestAnimationFrame(tick);
    });
    slider.addEventListener('input', function () { current.t = parseFloat(slider.value) * T; update(); });
  }

  // the simulation's verdict and events: marks on the time line, a numbered list
  function drawEvents() {
    if (!S) return;
    document.getElementById('title').classList.add(S.verdict.held ? 'held' : 'failed');
    var line = document.getElementById('timeline'), list = document.getElementById('events');
    line.hidden = false;
    document.getElementById('eventsfig').hidden = false;
    S.events.forEach(function (e) {
      var m = document.createElement('span');
      m.className = 'mark'; m.dataset.t = e.t; m.dataset.kind = e.kind;
      m.style.left = (T > 0 ? 100 * e.t / T : 0) + '%';
      m.style.background = hex(EVENT_COLORS[e.kind] || 0);
      m.textContent = e.number; m.title = e.t.toFixed(3) + ' s: ' + e.text;
      m.addEventListener('click', function () { current.t = e.t; update(); });
      line.appendChild(m);
      var li = document.createElement('li');
      li.dataset.t = e.t; li.dataset.kind = e.kind;
      li.textContent = e.t.toFixed(3) + ' s, ' + e.kind.replace('_', ' ') + ': ' + e.text;
      li.addEventListener('click', function () { current.t = e.t; update(); });
      list.appendChild(li);
    });
    if (!S.events.length) {
      var li = document.createElement('li');
      li.textContent = 'no event: ' + S.verdict.reason;
      list.appendChild(li);
    }
  }

  // ---- go -----------------------------------------------------------------------------
  drawTop();
  drawEvents();
  drawPhase();
  drawTable();
  if (webglAvailable()) {
    try {
      three = build3d();
      status.webgl = true;
    } catch (e) {
      status.errors.push('3-D view: ' + e.message);
      three = null;
    }
  }
  if (!three) {
    document.getElementById('three').hidden = true;
    document.getElementById('nowebgl').hidden = false;
    document.body.classList.add('nowebgl');
  }
  update();
  if (three) {
    status.counts = three.counts;
    status.counts.timeline_marks = document.querySelectorAll('#timeline .mark').length;
    status.draw_calls = three.renderer.info.render.calls;
    status.triangles = three.renderer.info.render.triangles;
    // pixel probe (on request, `#probe` in the address: reading pixels back stalls the GPU):
    // the first contact's centroid on screen with the contacts drawn alone, and a corner
    var st = D.stances[segmentAt()];
    if (/probe/.test(location.hash) && st && st.contacts.length) {
      var shown = [];
      three.scene.children.forEach(function (g) { if (g.isGroup) { shown.push([g, g.visible]); g.visible = g.name === 'contacts'; } });
      three.render();
      var v = st.contacts[0].vertices, cx = 0, cy = 0, cz = 0;
      v.forEach(function (p) { cx += p[0] / v.length; cy += p[1] / v.length; cz += p[2] / v.length; });
      var q = new THREE.Vector3(cx, cy, cz).project(three.camera);
      var gl = three.renderer.getContext();
      var w = gl.drawingBufferWidth, hgt = gl.drawingBufferHeight;
      var px = Math.round((q.x + 1) / 2 * (w - 1)), py = Math.round((q.y + 1) / 2 * (hgt - 1));
      var rgba = new Uint8Array(4), bg = new Uint8Array(4);
      gl.readPixels(px, py, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, rgba);
      gl.readPixels(1, 1, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, bg);
      status.probe = { contact: st.contacts[0].name, pixel: [px, py], rgba: Array.from(rgba), background: Array.from(bg) };
      shown.forEach(function (x) { x[0].visible = x[1]; });
      three.render();
    }
    // a link's probe (`#probe=LINK`): the robot alone, unlit (so that a pixel has the exact
    // colour of whatever mesh covers it), read at the on-screen centre of the link's first mesh
    var pl = /probe=([^&]+)/.exec(location.hash);
    if (pl && three.probeLink) status.link_probe = three.probeLink(decodeURIComponent(pl[1]));
  } else {
    status.counts = { stances: D.stances.length, contacts_2d: document.querySelectorAll('.contact2d').length };
  }
  status.ready = true;
  status.load_ms = Math.round(performance.now());
  publish();
  document.body.dataset.ready = '1';
  window.stanceView = { status: status, data: D, setTime: function (t) { current.t = t; update(); } };
})();
