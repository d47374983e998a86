// sinedec datasheet self-check (inline in index.html): collects every script, resource and
// console error, and once the page has loaded, the size of every figure's <svg> or <img>;
// writes both as JSON into the element #selfcheck for the browser test (tests/report/datasheet.rs).
(function () {
  var errors = [];
  window.addEventListener("error", function (e) {
    var t = e.target && e.target !== window ? (e.target.tagName || "element") + " failed to load" : e.message;
    errors.push(String(t));
  }, true);
  window.addEventListener("unhandledrejection", function (e) { errors.push("unhandled rejection: " + e.reason); });
  var original = console.error;
  console.error = function () {
    errors.push(Array.prototype.join.call(arguments, " "));
    return original.apply(console, arguments);
  };
  window.addEventListener("load", function () {
    var figures = Array.prototype.map.call(document.querySelectorAll("figure"), function (f) {
      var el = f.querySelector("svg, img");
      var r = el ? el.getBoundingClientRect() : { width: 0, height: 0 };
      var loaded = !!el && (el.tagName.toLowerCase() !== "img" || (el.complete && el.naturalWidth > 0));
      return { id: f.id, width: r.width, height: r.height, loaded: loaded };
    });
    document.getElementById("selfcheck").textContent = JSON.stringify({ figures: figures, errors: errors });
  });
})();
