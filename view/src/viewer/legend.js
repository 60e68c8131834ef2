  // ---- legend, toggles, cameras, picking --------------------------------------------------------------
  var legend = element('div');
  legend.id = 'hullmap-legend';
  document.body.appendChild(legend);
  var params = data.parameters || {};
  legend.appendChild(element('h1', '', 'hullmap view: ' + data.title));
  legend.appendChild(element('p', 'small', 'frame: ' + (data.frame || 'unknown')));
  var auto = function (key) { return params[key + '_auto'] ? ' (auto)' : ''; };
  legend.appendChild(element('p', 'small', 'resolution ' + text(params.resolution) + ', eps ' + text(params.eps) + auto('eps') +
                             ', minPts ' + text(params.min_pts) + auto('min_pts') + ', metric ' + text(params.metric) +
                             ', concavity ' + text(params.concavity) + ', floor ' + text(params.floor) +
                             ', ceiling ' + text(params.ceiling)));
  legend.appendChild(element('p', 'small', text(vx.total) + ' occupied voxels: ' + text(data.obstacles.length) +
                             ' obstacles, ' + text(vx.noise) + ' noise, ' + text(vx.floor) + ' floor, ' + text(vx.ceiling) +
                             ' ceiling; ' + text(data.hulls.items.length) + ' convex parts'));
  if (levels[0].factor > 1) {
    legend.appendChild(element('p', 'small notice', text(vx.total) + ' voxels are more than the ' + text(vx.max_instances) +
                               ' cubes this page holds (hullmap view --max-instances): its finest level merges them into ' +
                               text(levels[0].instances) + ' cells of ' + text(levels[0].cell) + ' map units (' +
                               levels[0].factor + ' voxels a side)'));
  }
  var detailRow = element('p', 'small');
  detailRow.appendChild(document.createTextNode('Detail: '));
  detailSelect = element('select');
  detailSelect.id = 'detail';
  levels.forEach(function (l, k) {
    var option = element('option', '', l.factor === 1 ? 'every voxel, ' + text(l.instances) + ' cubes'
                                       : 'cells of ' + text(l.cell) + ' (' + l.factor + ' voxels a side), ' +
                                         text(l.instances) + ' cubes');
    option.value = String(k);
    detailSelect.appendChild(option);
  });
  detailSelect.addEventListener('change', function () { setDetail(Number(detailSelect.value)); });
  detailRow.appendChild(detailSelect);
  var detailNote = element('span', 'small');
  detailRow.appendChild(detailNote);
  legend.appendChild(detailRow);
  (data.warnings || []).forEach(function (w) { legend.appendChild(element('p', 'small', 'warning: ' + w)); });
  legend.appendChild(element('h2', '', 'Layers'));
  layerOrder.forEach(function (name) {
    var l = layers[name];
    var row = element('label');
    var box = element('input');
    box.type = 'checkbox';
    box.checked = l.group.visible;
    box.id = 'layer-' + name;
    box.addEventListener('change', function () { setLayer(name, box.checked); });
    var swatch = element('span', 'swatch');
    swatch.style.background = l.swatch;
    row.appendChild(box);
    row.appendChild(swatch);
    row.appendChild(document.createTextNode(l.title + ': '));
    row.appendChild(element('span', 'small', l.detail));
    legend.appendChild(row);
  });
  if (view.paths.length > 0) {
    legend.appendChild(element('h2', '', 'Paths'));
    view.paths.forEach(function (p, i) {
      var row = element('p', 'small');
      var swatch = element('span', 'swatch');
      swatch.style.background = p.colour;
      row.appendChild(swatch);
      row.appendChild(document.createTextNode((p.name || 'path ' + i) + ', ' + p.segments.length + ' segments: '));
      if (p.collides) {
        var s = p.segments[p.first_colliding_segment];
        var what = s.surface ? 'the ' + s.surface : 'obstacle ' + s.obstacle + (s.part >= 0 ? ' part ' + s.part : '');
        row.appendChild(element('span', 'collides', 'COLLIDES with ' + what + ' on segment ' + p.first_colliding_segment +
                                ' at ' + point(p.first_contact)));
      } else {
        var clearance = Math.min.apply(null, p.segments.map(function (s) { return s.clearance === null ? Infinity : s.clearance; }));
        row.appendChild(element('span', 'clear', 'clear' + (isFinite(clearance) ? ', min clearance ' + text(clearance) : '')));
      }
      legend.appendChild(row);
    });
  }
  legend.appendChild(element('p', 'small', 'grid every ' + text(gridStep) + ' map units, axes x, y, z from its corner ' +
                             point(view.grid.corner) + '; drag to orbit, right-drag to pan, wheel to zoom; click a part ' +
                             'for its id. hullmap ' + (data.hullmap_version || '') + ', three.js r' + THREE.REVISION));

  var info = element('div');
  info.id = 'hullmap-info';
  document.body.appendChild(info);

  var cameras = element('div');
  cameras.id = 'hullmap-cameras';
  var buttons = {};
  ['top', 'side', 'free'].forEach(function (name) {
    var b = element('button', '', name === 'top' ? 'Top' : name === 'side' ? 'Side' : 'Free');
    b.id = 'camera-' + name;
    b.addEventListener('click', function () { setCamera(name); });
    buttons[name] = b;
    cameras.appendChild(b);
  });
  document.body.appendChild(cameras);

  var pending = false;
  function render() {
    pending = false;
    renderer.render(scene, camera);
    updateScale();
  }
  function requestRender() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(render);
  }
  controls.addEventListener('change', requestRender);
  // The legend covers the left of the window: the camera centres the map in the rest of it (the
  // projection's centre moves right by half the legend's width).
  var legendWidth = 0;
  var freeAspect = camera.aspect;  // of the part of the window the legend leaves free
  function fitWindow() {
    var w = window.innerWidth, h = window.innerHeight;
    legendWidth = w > 2.5 * (legend.offsetWidth + 16) ? legend.offsetWidth + 16 : 0;
    freeAspect = (w - legendWidth) / h;
    camera.setViewOffset(w + legendWidth, h, 0, 0, w, h);
    renderer.setSize(w, h, false);
  }
  window.addEventListener('resize', function () {
    fitWindow();
    requestRender();
  });

  function setLayer(name, visible) {
    if (!layers[name]) throw new Error('no layer ' + name);
    layers[name].group.visible = !!visible;
    var box = document.getElementById('layer-' + name);
    if (box) box.checked = !!visible;
    render();
  }
  function setCamera(name) {
    var half = Math.tan(camera.fov * Math.PI / 360);
    var fit = function (w, h) { return 1.1 * Math.max(h / 2 / half, w / 2 / (half * freeAspect)); };
    var dx = boxMax.x - boxMin.x, dy = boxMax.y - boxMin.y, dz = boxMax.z - boxMin.z;
    var offset;
    if (name === 'top') {
      var d = fit(dx, dy) + dz / 2;
      offset = new THREE.Vector3(0, -1e-3 * d, d);
    } else if (name === 'side') {
      offset = new THREE.Vector3(0, -(fit(dx, dz) + dy / 2), 0);
    } else if (name === 'free') {
      var r = 0.5 * boxMin.distanceTo(boxMax);
      offset = new THREE.Vector3(-0.45, -0.8, 0.62).normalize().multiplyScalar(1.05 * r / Math.min(half, half * freeAspect));
    } else {
      throw new Error('no camera ' + name);
    }
    controls.target.copy(centre);
    camera.position.copy(centre).add(offset);
    controls.update();
    Object.keys(buttons).forEach(function (k) { buttons[k].className = k === name ? 'active' : ''; });
    view.camera = name;
    render();
  }

  // The camera at `eye` looking at `target` (map frame): for tools that want a given picture.
  function setView(eye, target) {
    controls.target.copy(local(target));
    camera.position.copy(local(eye));
    controls.update();
    Object.keys(buttons).forEach(function (k) { buttons[k].className = ''; });
    view.camera = 'custom';
    render();
  }

