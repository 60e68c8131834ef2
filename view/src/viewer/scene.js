  // ---- the scene --------------------------------------------------------------------------------
  var canvas = document.createElement('canvas');
  canvas.id = 'hullmap-canvas';
  document.body.appendChild(canvas);
  var renderer;
  try {
    renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true, preserveDrawingBuffer: true});
  } catch (e) {
    // Without WebGL nothing can be drawn: say so on the page (hullmapView.ready stays false).
    var message = element('div', '', 'hullmap view: this browser gives the page no WebGL (' + e.message + '), and ' +
                          'the page draws with WebGL. Open it in a browser with WebGL on (any current Chromium or ' +
                          'Firefox with graphics acceleration, or a software renderer). The build: ' + data.title + ', ' +
                          data.voxels.total + ' voxels, ' + data.obstacles.length + ' obstacles.');
    message.id = 'hullmap-no-webgl';
    document.body.appendChild(message);
    view.errors.push('no WebGL: ' + e.message);
    return;
  }
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(window.innerWidth, window.innerHeight, false);
  var scene = new THREE.Scene();
  scene.background = new THREE.Color(0xffffff);
  scene.add(new THREE.AmbientLight(0xffffff, 0.62));
  var sun = new THREE.DirectionalLight(0xffffff, 0.5);
  sun.position.set(0.45, -0.65, 1.0);
  scene.add(sun);

  var boxMin = local(data.view.min), boxMax = local(data.view.max);
  var centre = boxMin.clone().add(boxMax).multiplyScalar(0.5);
  var size = Math.max(boxMax.x - boxMin.x, boxMax.y - boxMin.y, boxMax.z - boxMin.z, 1e-3);
  var camera = new THREE.PerspectiveCamera(40, window.innerWidth / window.innerHeight, size / 2000, size * 200);
  camera.up.set(0, 0, 1);
  var controls = new THREE.OrbitControls(camera, canvas);
  controls.screenSpacePanning = true;

  var layers = {};
  var layerOrder = [];
  function layer(name, title, swatch, detail, visible) {
    var group = new THREE.Group();
    group.name = name;
    group.visible = visible !== false;
    scene.add(group);
    layers[name] = {group: group, title: title, swatch: swatch, detail: detail};
    layerOrder.push(name);
    return group;
  }

  // A rod (thin cylinder) from a to b, local coordinates.
  var yAxis = new THREE.Vector3(0, 1, 0);
  function rod(a, b, radius, material) {
    var d = b.clone().sub(a);
    var length = d.length();
    if (!(length > 0)) return null;
    var mesh = new THREE.Mesh(new THREE.CylinderBufferGeometry(radius, radius, length, 10, 1, false), material);
    mesh.position.copy(a).add(b).multiplyScalar(0.5);
    mesh.quaternion.setFromUnitVectors(yAxis, d.divideScalar(length));
    return mesh;
  }
  function sphere(p, radius, material, segments) {
    var mesh = new THREE.Mesh(new THREE.SphereBufferGeometry(radius, segments || 12, Math.max(6, (segments || 12) * 2 / 3)),
                              material);
    mesh.position.copy(p);
    return mesh;
  }
  // A text label facing the camera, `height` map units tall.
  function label(content, p, height, hex) {
    var c = document.createElement('canvas');
    var context = c.getContext('2d');
    var font = 'bold 40px sans-serif';
    context.font = font;
    var width = Math.ceil(context.measureText(content).width) + 12;
    c.width = width;
    c.height = 52;
    context.font = font;
    context.lineWidth = 8;
    context.strokeStyle = 'rgba(255,255,255,0.9)';
    context.strokeText(content, 6, 40);
    context.fillStyle = hex || '#111111';
    context.fillText(content, 6, 40);
    var texture = new THREE.CanvasTexture(c);
    texture.minFilter = THREE.LinearFilter;
    var sprite = new THREE.Sprite(new THREE.SpriteMaterial({map: texture, depthTest: false, transparent: true}));
    sprite.scale.set(height * width / 52, height, 1);
    sprite.position.copy(p);
    sprite.renderOrder = 10;
    return sprite;
  }
  function lineSegments(positions, hex, opacity) {
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    var m = new THREE.LineBasicMaterial({color: hex, transparent: opacity < 1, opacity: opacity === undefined ? 1 : opacity});
    return new THREE.LineSegments(g, m);
  }

  // ---- voxels: instanced cubes, one colour per instance, at levels of detail ----------------------
  // The page holds its voxels at several levels (cells of 1, 2, 4, ... voxels a side, each cell in the
  // colour of an obstacle it holds, else noise, else floor). It draws the finest level that a frame
  // of this machine draws in about kFrameTargetMs (measured on the coarsest when the page loads);
  // the legend's Detail list picks another.
  var kFrameTargetMs = 100;
  var vx = data.voxels;
  var levels = vx.levels;
  var cube = new THREE.BoxBufferGeometry(1, 1, 1);
  // r111's InstancedMesh has no per-instance colour: an instanceColor attribute replaces the
  // vertex colour in the Lambert shader.
  function instancedMaterial(opacity) {
    var m = new THREE.MeshLambertMaterial({vertexColors: THREE.VertexColors, transparent: opacity < 1,
                                           opacity: opacity, depthWrite: opacity >= 1});
    m.onBeforeCompile = function (shader) {
      shader.vertexShader = 'attribute vec3 instanceColor;\n' +
        shader.vertexShader.replace('#include <color_vertex>', 'vColor.xyz = instanceColor;');
    };
    return m;
  }
  function voxelClass(label) { return label >= 0 ? 'voxels' : label === -1 ? 'noise' : 'surfaces'; }
  var voxelStats = {total: vx.total, clustered: vx.clustered, noise: vx.noise, floor: vx.floor, ceiling: vx.ceiling,
                    max_instances: vx.max_instances, target_ms: kFrameTargetMs,
                    levels: levels.map(function (l) { return {factor: l.factor, cell: l.cell, instances: l.instances}; }),
                    labels: {}};
  // Per label of the finest level: its cubes and the sum of their centres (map frame).
  (function () {
    var L = levels[0], cells = uint16s(L.cells), i = 0;
    L.groups.forEach(function (g) {
      var sum = [0, 0, 0];
      for (var end = i + g.count; i < end; i++)
        for (var a = 0; a < 3; a++) sum[a] += L.origin[a] + cells[3 * i + a] * L.cell;
      voxelStats.labels[g.label] = {cells: g.count, sum: sum};
    });
  })();
  var cellNote = levels[0].factor > 1 ? ' (merged cells)' : '';
  var voxelLayers = {
    voxels: layer('voxels', 'obstacle voxels', '#e68fac', text(vx.clustered) + ' voxels, coloured by obstacle' + cellNote),
    noise: layer('noise', 'noise voxels', data.colours.noise, text(vx.noise) + ' voxels in no obstacle' + cellNote),
    surfaces: layer('surfaces', 'floor and ceiling voxels', data.colours.floor,
                    text(vx.floor) + ' floor, ' + text(vx.ceiling) + ' ceiling voxels, not clustered' + cellNote)};
  var builtLevels = [];
  function buildLevel(k) {
    if (builtLevels[k]) return builtLevels[k];
    var L = levels[k];
    var cells = uint16s(L.cells);
    var byClass = {voxels: [], noise: [], surfaces: []};
    var first = 0;
    L.groups.forEach(function (g) {
      byClass[voxelClass(g.label)].push({colour: g.colour, first: first, count: g.count});
      first += g.count;
    });
    var fill = 0.9 * L.cell;  // a gap between cubes shows single voxels
    function build(groups, opacity) {
      var count = 0;
      groups.forEach(function (g) { count += g.count; });
      if (count === 0) return null;
      var geometry = cube.clone();
      var mesh = new THREE.InstancedMesh(geometry, instancedMaterial(opacity), count);
      var matrices = mesh.instanceMatrix.array;
      var colours = new Float32Array(3 * count);
      var k = 0;
      groups.forEach(function (g) {
        var c = colour(g.colour);
        for (var i = g.first; i < g.first + g.count; i++, k++) {
          var o = 16 * k;
          matrices[o] = fill; matrices[o + 5] = fill; matrices[o + 10] = fill; matrices[o + 15] = 1;
          matrices[o + 12] = L.origin[0] + cells[3 * i] * L.cell - shift[0];
          matrices[o + 13] = L.origin[1] + cells[3 * i + 1] * L.cell - shift[1];
          matrices[o + 14] = L.origin[2] + cells[3 * i + 2] * L.cell - shift[2];
          colours[3 * k] = c.r; colours[3 * k + 1] = c.g; colours[3 * k + 2] = c.b;
        }
      });
      geometry.setAttribute('instanceColor', new THREE.InstancedBufferAttribute(colours, 3));
      mesh.instanceMatrix.needsUpdate = true;
      // Three's culling would test the one cube at the origin, not the instances.
      mesh.frustumCulled = false;
      return mesh;
    }
    var surfaces = build(byClass.surfaces, 0.16);
    if (surfaces) surfaces.renderOrder = 1;
    builtLevels[k] = {voxels: build(byClass.voxels, 1), noise: build(byClass.noise, 1), surfaces: surfaces};
    return builtLevels[k];
  }
  var shownLevel = -1;
  var detailSelect = null;
  function showLevel(k) {
    if (k < 0 || k >= levels.length) throw new Error('no level ' + k);
    if (shownLevel >= 0) {
      var old = builtLevels[shownLevel];
      Object.keys(voxelLayers).forEach(function (c) { if (old[c]) voxelLayers[c].remove(old[c]); });
    }
    var b = buildLevel(k);
    Object.keys(voxelLayers).forEach(function (c) { if (b[c]) voxelLayers[c].add(b[c]); });
    shownLevel = k;
    voxelStats.level = k;
    voxelStats.instances = levels[k].instances;
    voxelStats.cell = levels[k].cell;
    voxelStats.factor = levels[k].factor;
    voxelStats.merged = levels[k].factor > 1;
    if (detailSelect) detailSelect.value = String(k);
  }
  view.voxels = voxelStats;

  // ---- convex parts -----------------------------------------------------------------------------
  // All hulls in one translucent mesh and one set of edges (thousands of parts would otherwise be
  // thousands of draw calls); the parts a path hits and the part clicked are drawn again on top.
  var hulls = [];         // per hull: its item, first triangle in the merged mesh, its geometry
  var hullFaces = null;   // the merged mesh, for picking
  view.parts = [];
  var partsGroup = layer('parts', 'convex parts', '#875692', data.hulls.items.length + ' hulls of ' +
                         data.obstacles.length + ' obstacles; click one');
  function hullOverlay(h, opacity, edgeHex) {
    var group = new THREE.Group();
    group.add(new THREE.Mesh(h.faces, new THREE.MeshLambertMaterial({color: h.item.colour, transparent: true,
                                                                     opacity: opacity, depthWrite: false})));
    group.add(new THREE.LineSegments(h.edges, new THREE.LineBasicMaterial({color: edgeHex})));
    return group;
  }
  (function () {
    var H = data.hulls;
    var vertices = floats(H.vertices);
    var triangles = uint32s(H.triangles);
    var faceCount = 0;
    H.triangle_counts.forEach(function (n) { faceCount += n; });
    var facePositions = new Float32Array(9 * faceCount), faceColours = new Float32Array(9 * faceCount);
    var edgePositions = [], edgeColours = [];
    var vo = 0, to = 0;
    H.items.forEach(function (item, i) {
      var nv = H.vertex_counts[i], nt = H.triangle_counts[i];
      var geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(vertices.slice(3 * vo, 3 * (vo + nv)), 3));
      geometry.setIndex(new THREE.BufferAttribute(new Uint16Array(triangles.subarray(3 * to, 3 * (to + nt))), 1));
      var faces = geometry.toNonIndexed();
      faces.computeVertexNormals();
      var edges = new THREE.EdgesGeometry(geometry, 1);
      var c = colour(item.colour);
      facePositions.set(faces.attributes.position.array, 9 * to);
      for (var k = 9 * to; k < 9 * (to + nt); k += 3) { faceColours[k] = c.r; faceColours[k + 1] = c.g; faceColours[k + 2] = c.b; }
      var e = edges.attributes.position.array;
      for (k = 0; k < e.length; k += 3) {
        edgePositions.push(e[k], e[k + 1], e[k + 2]);
        edgeColours.push(c.r, c.g, c.b);
      }
      hulls.push({item: item, first: to, count: nt, faces: faces, edges: edges});
      view.parts.push({obstacle: item.obstacle, part: item.part, volume: item.volume, voxels: item.voxels,
                       vertices: nv, triangles: nt, colour: item.colour, flat: item.flat});
      vo += nv;
      to += nt;
    });
    var merged = new THREE.BufferGeometry();
    merged.setAttribute('position', new THREE.BufferAttribute(facePositions, 3));
    merged.setAttribute('color', new THREE.BufferAttribute(faceColours, 3));
    merged.computeVertexNormals();
    // Outward triangles, seen from outside only: half the blending of both sides.
    hullFaces = new THREE.Mesh(merged, new THREE.MeshLambertMaterial({vertexColors: THREE.VertexColors, transparent: true,
                                                                      opacity: 0.3, depthWrite: false}));
    partsGroup.add(hullFaces);
    var lines = new THREE.BufferGeometry();
    lines.setAttribute('position', new THREE.BufferAttribute(new Float32Array(edgePositions), 3));
    lines.setAttribute('color', new THREE.BufferAttribute(new Float32Array(edgeColours), 3));
    partsGroup.add(new THREE.LineSegments(lines, new THREE.LineBasicMaterial({vertexColors: THREE.VertexColors})));
  })();
  view.obstacles = data.obstacles;
  // The hull a triangle of the merged mesh belongs to.
  function hullOfFace(face) {
    var lo = 0, hi = hulls.length - 1;
    while (lo < hi) {
      var mid = (lo + hi + 1) >> 1;
      if (hulls[mid].first <= face) lo = mid; else hi = mid - 1;
    }
    return hulls[lo];
  }

  // ---- floor and ceiling planes -------------------------------------------------------------------
  view.floor = data.floor;
  view.ceiling = data.ceiling;
  (function () {
    var group = null;
    [['floor', data.floor, data.colours.floor_plane], ['ceiling', data.ceiling, data.colours.ceiling_plane]].forEach(function (s) {
      var plane = s[1];
      if (!plane || Math.abs(plane.normal[2]) < 0.05) return;
      if (!group) group = layer('floor', 'floor' + (data.ceiling ? ' and ceiling' : ''), s[2], 'found by the build');
      var grow = 0.08 * size;
      var x0 = boxMin.x - grow, x1 = boxMax.x + grow, y0 = boxMin.y - grow, y1 = boxMax.y + grow;
      var n = plane.normal;
      // n . (p + shift) = offset, so in local coordinates n . p = offset - n . shift.
      var d = plane.offset - (n[0] * shift[0] + n[1] * shift[1] + n[2] * shift[2]);
      function z(x, y) { return (d - n[0] * x - n[1] * y) / n[2]; }
      var corners = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]].map(function (c) { return new THREE.Vector3(c[0], c[1], z(c[0], c[1])); });
      var geometry = new THREE.BufferGeometry().setFromPoints([corners[0], corners[1], corners[2], corners[0], corners[2], corners[3]]);
      var mesh = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({color: s[2], transparent: true, opacity: 0.2,
                                                                        side: THREE.DoubleSide, depthWrite: false}));
      mesh.renderOrder = -1;
      group.add(mesh);
      group.add(new THREE.LineLoop(new THREE.BufferGeometry().setFromPoints(corners),
                                   new THREE.LineBasicMaterial({color: s[2]})));
      group.add(label(s[0], corners[0], 0.03 * size, '#555'));
    });
  })();

  // ---- keyframe trajectory --------------------------------------------------------------------------
  view.keyframes = data.keyframes ? data.keyframes.count : 0;
  if (data.keyframes) {
    var kf = data.keyframes;
    var kfGroup = layer('keyframes', 'keyframe trajectory', data.colours.keyframes, kf.count + ' keyframes (trajectory.txt)');
    var kfGeometry = new THREE.BufferGeometry();
    kfGeometry.setAttribute('position', new THREE.BufferAttribute(floats(kf.positions), 3));
    kfGroup.add(new THREE.Line(kfGeometry, new THREE.LineBasicMaterial({color: data.colours.keyframes})));
    kfGroup.add(new THREE.Points(kfGeometry, new THREE.PointsMaterial({color: data.colours.keyframes, size: 5,
                                                                       sizeAttenuation: false})));
    kfGroup.add(lineSegments(floats(kf.ticks), data.colours.keyframes, 0.8));
  }

  // ---- paths with their checks ------------------------------------------------------------------------
  view.paths = [];
  var hitHulls = {};
  if (data.paths.length > 0) {
    var pathGroup = layer('paths', 'checked paths', data.colours.clear,
                          data.paths.length + ' at radius ' + text(data.radius) + ': green clear, red from the first contact');
    var rodRadius = Math.max(0.4 * data.resolution, 0.006 * size);
    var clearMaterial = new THREE.MeshBasicMaterial({color: data.colours.clear});
    var collideMaterial = new THREE.MeshBasicMaterial({color: data.colours.collides});
    data.paths.forEach(function (path, index) {
      var w = path.waypoints.map(local);
      var first = path.first_colliding_segment;
      var contact = path.first_contact ? local(path.first_contact) : null;
      var bandMaterial = new THREE.MeshLambertMaterial({color: path.colour, transparent: true, opacity: 0.13, depthWrite: false});
      for (var i = 0; i + 1 < w.length; i++) {
        var pieces = first === null || i < first ? [[w[i], w[i + 1], clearMaterial]]
                   : i > first ? [[w[i], w[i + 1], collideMaterial]]
                   : [[w[i], contact, clearMaterial], [contact, w[i + 1], collideMaterial]];
        pieces.forEach(function (piece) {
          var r = rod(piece[0], piece[1], rodRadius, piece[2]);
          if (r) pathGroup.add(r);
        });
        if (data.radius > 0) {
          var band = rod(w[i], w[i + 1], data.radius, bandMaterial);
          if (band) pathGroup.add(band);
        }
      }
      var waypointMaterial = new THREE.MeshBasicMaterial({color: path.colour});
      w.forEach(function (p) { pathGroup.add(sphere(p, 1.8 * rodRadius, waypointMaterial, 10)); });
      var hit = null;
      if (contact) {
        pathGroup.add(sphere(contact, 2.6 * rodRadius, collideMaterial, 14));
        if (data.radius > 0) {
          pathGroup.add(sphere(contact, data.radius, new THREE.MeshBasicMaterial({color: data.colours.collides, wireframe: true,
                                                                                  transparent: true, opacity: 0.6}), 16));
        }
        var s = path.segments[first];
        hit = {obstacle: s.obstacle, part: s.part, surface: s.surface || null};
        if (s.obstacle !== null) hitHulls[s.obstacle + '/' + s.part] = true;
        pathGroup.add(label('first contact' + (data.paths.length > 1 ? ' (' + path.name + ')' : ''),
                            contact.clone().add(new THREE.Vector3(0, 0, 2.2 * Math.max(data.radius, rodRadius))),
                            0.018 * size, data.colours.collides));
      }
      view.paths.push({name: path.name, colour: path.colour, radius: data.radius, waypoints: path.waypoints,
                       segments: path.segments, collides: first !== null, first_colliding_segment: first,
                       first_contact: path.first_contact, hit: hit});
    });
  }
  // The obstacle a path hits first: all its parts more opaque, the part hit outlined in red.
  hulls.forEach(function (h) {
    var hitObstacle = Object.keys(hitHulls).some(function (k) { return Number(k.split('/')[0]) === h.item.obstacle; });
    if (!hitObstacle) return;
    partsGroup.add(hullOverlay(h, 0.5, hitHulls[h.item.obstacle + '/' + h.item.part] ? data.colours.collides : h.item.colour));
  });

  // ---- roadmap --------------------------------------------------------------------------------------
  view.roadmap = null;
  if (data.roadmap) {
    var rm = data.roadmap;
    var rmGroup = layer('roadmap', 'roadmap', data.colours.roadmap, rm.edges + ' edges, ' + rm.nodes + ' nodes at z ' +
                        text(rm.z) + (rm.name ? ' (' + rm.name + ')' : ''));
    rmGroup.add(lineSegments(floats(rm.edge_segments), data.colours.roadmap, 0.9));
    var ng = new THREE.BufferGeometry();
    ng.setAttribute('position', new THREE.BufferAttribute(floats(rm.node_positions), 3));
    rmGroup.add(new THREE.Points(ng, new THREE.PointsMaterial({color: data.colours.roadmap, size: 4, sizeAttenuation: false})));
    view.roadmap = {nodes: rm.nodes, edges: rm.edges, z: rm.z};
  }

  // ---- ground truth ---------------------------------------------------------------------------------
  view.truth = null;
  if (data.truth) {
    var tr = data.truth;
    var trGroup = layer('truth', 'ground truth', data.colours.truth, tr.shapes.length + ' shapes, wireframes' +
                        (tr.name ? ' (' + tr.name + ')' : ''));
    var segments = floats(tr.segments);
    var so = 0;
    var solid = [], surface = [];
    tr.shapes.forEach(function (s) {
      var target = s.surface ? surface : solid;
      for (var i = so; i < so + s.segments; i++) for (var a = 0; a < 6; a++) target.push(segments[6 * i + a]);
      so += s.segments;
    });
    trGroup.add(lineSegments(new Float32Array(solid), data.colours.truth, 0.85));
    if (surface.length) trGroup.add(lineSegments(new Float32Array(surface), data.colours.truth, 0.3));
    view.truth = {shapes: tr.shapes.length, segments: so};
  }

  // ---- grid, axes and scale ---------------------------------------------------------------------------
  var gridStep = niceStep(size / 12);
  function niceStep(target) {
    var p = Math.pow(10, Math.floor(Math.log10(target)));
    var m = target / p;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
  }
  (function () {
    var group = layer('grid', 'grid and axes', '#bbbbbb', 'grid every ' + text(gridStep) + ' map units');
    // In the plane of the floor when it is level enough, else under everything.
    var z0 = boxMin.z;
    if (data.floor && Math.abs(data.floor.normal[2]) > 0.99) {
      var n = data.floor.normal;
      z0 = (data.floor.offset - n[0] * (centre.x + shift[0]) - n[1] * (centre.y + shift[1])) / n[2] - shift[2];
    }
    // Lines at whole multiples of the step in absolute coordinates.
    var ax0 = Math.floor((boxMin.x + shift[0] - 0.05 * size) / gridStep), ax1 = Math.ceil((boxMax.x + shift[0] + 0.05 * size) / gridStep);
    var ay0 = Math.floor((boxMin.y + shift[1] - 0.05 * size) / gridStep), ay1 = Math.ceil((boxMax.y + shift[1] + 0.05 * size) / gridStep);
    var lines = [];
    var x0 = ax0 * gridStep - shift[0], x1 = ax1 * gridStep - shift[0];
    var y0 = ay0 * gridStep - shift[1], y1 = ay1 * gridStep - shift[1];
    for (var i = ax0; i <= ax1; i++) lines.push(i * gridStep - shift[0], y0, z0, i * gridStep - shift[0], y1, z0);
    for (var j = ay0; j <= ay1; j++) lines.push(x0, j * gridStep - shift[1], z0, x1, j * gridStep - shift[1], z0);
    var grid = lineSegments(new Float32Array(lines), 0xcfcfcf, 1);
    grid.renderOrder = -2;
    group.add(grid);
    var labelHeight = 0.022 * size;
    var every = Math.max(1, Math.ceil((ax1 - ax0) / 10));
    for (i = ax0; i <= ax1; i += every)
      group.add(label(text(i * gridStep), new THREE.Vector3(i * gridStep - shift[0], y0 - 1.5 * labelHeight, z0), labelHeight, '#444'));
    every = Math.max(1, Math.ceil((ay1 - ay0) / 10));
    for (j = ay0; j <= ay1; j += every)
      group.add(label(text(j * gridStep), new THREE.Vector3(x0 - 2.5 * labelHeight, j * gridStep - shift[1], z0), labelHeight, '#444'));
    // Axes from the grid's corner, one step long.
    var corner = new THREE.Vector3(x0, y0, z0);
    var axisRadius = 0.004 * size;
    [['x', [1, 0, 0], data.colours.axis_x], ['y', [0, 1, 0], data.colours.axis_y], ['z', [0, 0, 1], data.colours.axis_z]]
      .forEach(function (a) {
        var end = corner.clone().add(new THREE.Vector3(a[1][0], a[1][1], a[1][2]).multiplyScalar(2 * gridStep));
        group.add(rod(corner, end, axisRadius, new THREE.MeshBasicMaterial({color: a[2]})));
        group.add(label(a[0], end.clone().add(new THREE.Vector3(a[1][0], a[1][1], a[1][2]).multiplyScalar(0.4 * gridStep)),
                        1.4 * labelHeight, a[2]));
      });
    view.grid = {step: gridStep, z: z0 + shift[2], corner: absolute(corner)};
  })();

  var scaleBox = element('div');
  scaleBox.id = 'hullmap-scale';
  var scaleBar = element('div');
  var scaleText = element('span');
  scaleBox.appendChild(scaleBar);
  scaleBox.appendChild(scaleText);
  document.body.appendChild(scaleBox);
  function updateScale() {
    // Pixels per map unit at the orbit target's depth.
    var distance = camera.position.distanceTo(controls.target);
    var visible = 2 * distance * Math.tan(camera.fov * Math.PI / 360);
    var perUnit = canvas.clientHeight / visible;
    var length = niceStep(120 / perUnit);
    scaleBar.style.width = Math.round(length * perUnit) + 'px';
    scaleText.textContent = text(length) + (length === 1 ? ' map unit' : ' map units') + ' at the orbit centre';
  }

