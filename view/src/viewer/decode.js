// hullmap view: draws the page's data (the JSON block #hullmap-data, written by hullmap::view) with
// three.js r111. Everything is in the build's output frame, z up, map units; the typed arrays hold
// coordinates relative to data.shift (float32 keeps centimetres at any distance from the origin).
// window.hullmapView is the page's summary: what was decoded and drawn, for people and for tests.
(function () {
  'use strict';

  var view = window.hullmapView = {ready: false, errors: window.hullmapErrors || []};
  var data = JSON.parse(document.getElementById('hullmap-data').textContent);
  var shift = data.shift;

  // ---- decoding -------------------------------------------------------------------------------
  function bytes(text) {
    var binary = atob(text || '');
    var n = binary.length;
    var out = new Uint8Array(n);
    for (var i = 0; i < n; i++) out[i] = binary.charCodeAt(i);
    return out;
  }
  function floats(text) { return new Float32Array(bytes(text).buffer); }
  function uint16s(text) { return new Uint16Array(bytes(text).buffer); }
  function uint32s(text) { return new Uint32Array(bytes(text).buffer); }
  function local(p) { return new THREE.Vector3(p[0] - shift[0], p[1] - shift[1], p[2] - shift[2]); }
  function absolute(v) { return [v.x + shift[0], v.y + shift[1], v.z + shift[2]]; }
  function colour(hex) { return new THREE.Color(hex); }

  function text(value, digits) {
    if (value === null || value === undefined) return '-';
    if (typeof value !== 'number') return String(value);
    if (Number.isInteger(value)) return value.toLocaleString('en-US');
    return String(Number(value.toPrecision(digits || 4)));
  }
  function point(p) { return '(' + p.map(function (v) { return text(v, 4); }).join(' ') + ')'; }
  function element(tag, className, content) {
    var e = document.createElement(tag);
    if (className) e.className = className;
    if (content !== undefined) e.textContent = content;
    return e;
  }

