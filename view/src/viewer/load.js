  // Median wall time of `n` frames rendered one after another, each finished (read back) before the
  // next, the camera turning a little between them.
  function measureFrames(n) {
    var gl = renderer.getContext();
    var pixel = new Uint8Array(4);
    var times = [];
    for (var i = 0; i < n; i++) {
      camera.position.sub(controls.target).applyAxisAngle(new THREE.Vector3(0, 0, 1), 0.01).add(controls.target);
      camera.lookAt(controls.target);
      var t = performance.now();
      renderer.render(scene, camera);
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
      times.push(performance.now() - t);
    }
    times.sort(function (a, b) { return a - b; });
    controls.update();
    render();
    return {frames: n, median_ms: times[Math.floor(n / 2)], min_ms: times[0], max_ms: times[n - 1]};
  }

  view.title = data.title;
  view.format = data.format;
  view.frame = data.frame;
  view.parameters = data.parameters;
  view.report = data.report;
  view.three_revision = THREE.REVISION;
  view.layers = function () {
    var out = {};
    layerOrder.forEach(function (name) { out[name] = layers[name].group.visible; });
    return out;
  };
  view.setLayer = setLayer;
  view.setCamera = setCamera;
  view.setDetail = setDetail;
  view.setView = setView;
  view.pickAt = pickAt;
  view.project = project;
  view.measureFrames = measureFrames;

  function setDetail(k) {
    showLevel(k);
    detailNote.textContent = voxelStats.merged ? ' (merged: each cell in the colour of an obstacle it holds, else noise, ' +
                                                 'else floor)' : '';
    render();
  }
  // One frame, drawn and read back: its wall time.
  function timeFrame() {
    var gl = renderer.getContext();
    var t = performance.now();
    renderer.render(scene, camera);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
    return performance.now() - t;
  }
  // The finest level whose frames take about kFrameTargetMs here, from a frame of the coarsest one
  // and one without voxels (each after a frame that compiles what it needs).
  function chooseDetail() {
    var coarsest = levels.length - 1;
    showLevel(coarsest);
    timeFrame();
    var withVoxels = timeFrame();
    Object.keys(voxelLayers).forEach(function (c) { voxelLayers[c].visible = false; });
    var without = timeFrame();
    Object.keys(voxelLayers).forEach(function (c) { voxelLayers[c].visible = true; });
    var perCube = Math.max(withVoxels - without, 0) / Math.max(levels[coarsest].instances, 1);
    var chosen = coarsest;
    for (var k = 0; k < coarsest; k++) {
      if (without + perCube * levels[k].instances <= kFrameTargetMs) {
        chosen = k;
        break;
      }
    }
    voxelStats.chosen = chosen;
    voxelStats.frame_ms = withVoxels;
    voxelStats.frame_without_voxels_ms = without;
    voxelStats.cube_us = 1000 * perCube;
    return chosen;
  }

  fitWindow();
  setCamera('free');
  setDetail(levels.length > 1 ? chooseDetail() : 0);
  if (levels.length > 1) {
    detailNote.textContent += '; chosen here: a frame of ' + text(levels[levels.length - 1].instances) + ' cubes took ' +
      text(voxelStats.frame_ms, 3) + ' ms, and the finest level drawn within about ' + kFrameTargetMs + ' ms a frame is shown';
  }
  // Loaded: the first frame is drawn and read back.
  var gl = renderer.getContext();
  gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
  view.load_ms = performance.now();
  view.ready = true;
})();
