  function describe(h) {
    var item = h.item;
    return {obstacle: item.obstacle, part: item.part, volume: item.volume, voxels: item.voxels};
  }
  var selectedOverlay = null;
  function select(h) {
    if (selectedOverlay) partsGroup.remove(selectedOverlay);
    selectedOverlay = h ? hullOverlay(h, 0.65, '#000000') : null;
    if (selectedOverlay) partsGroup.add(selectedOverlay);
    view.selected = h ? describe(h) : null;
    info.textContent = '';
    info.style.display = h ? 'block' : 'none';
    if (!h) return;
    var s = view.selected;
    info.appendChild(element('b', '', 'obstacle ' + s.obstacle + (s.part >= 0 ? ' part ' + s.part : '')));
    info.appendChild(element('div', '', 'volume ' + text(s.volume) + ' map units\u00b3'));
    info.appendChild(element('div', '', s.voxels + ' voxels'));
    if (h.item.flat) info.appendChild(element('div', 'small', 'flat part (bounded by the flat gap)'));
  }
  var raycaster = new THREE.Raycaster();
  function pickAt(x, y) {
    if (!layers.parts || !layers.parts.group.visible) return null;
    var rect = canvas.getBoundingClientRect();
    var ndc = new THREE.Vector2((x - rect.left) / rect.width * 2 - 1, -(y - rect.top) / rect.height * 2 + 1);
    raycaster.setFromCamera(ndc, camera);
    var hits = raycaster.intersectObject(hullFaces);
    select(hits.length ? hullOfFace(hits[0].faceIndex) : null);
    render();
    return view.selected;
  }
  var down = null;
  canvas.addEventListener('mousedown', function (e) { down = [e.clientX, e.clientY]; });
  canvas.addEventListener('mouseup', function (e) {
    if (down && Math.abs(e.clientX - down[0]) + Math.abs(e.clientY - down[1]) < 5) pickAt(e.clientX, e.clientY);
    down = null;
  });

  // Screen position (CSS pixels) of a point of the map, for tests and tools.
  function project(p) {
    var v = local(p).project(camera);
    var rect = canvas.getBoundingClientRect();
    return [rect.left + (v.x + 1) / 2 * rect.width, rect.top + (1 - v.y) / 2 * rect.height, v.z];
  }
