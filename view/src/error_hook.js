// Collects the page's errors (uncaught exceptions, rejected promises, console.error: three.js reports
// shader and WebGL failures there) into window.hullmapErrors, which hullmapView.errors shows.
window.hullmapErrors = [];
window.addEventListener('error', function (e) {
  window.hullmapErrors.push(String(e.message || e.type) + (e.filename ? ' (' + e.filename + ':' + e.lineno + ')' : ''));
});
window.addEventListener('unhandledrejection', function (e) {
  window.hullmapErrors.push('unhandled rejection: ' + e.reason);
});
(function () {
  var original = console.error;
  console.error = function () {
    window.hullmapErrors.push(Array.prototype.join.call(arguments, ' '));
    return original.apply(console, arguments);
  };
})();
