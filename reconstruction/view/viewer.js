/* The histo viewer: a city model of v.histo.lod2 or v.histo.timeline in the browser.
 *
 * Written into one self-contained HTML file by reconstruction/view/html.py, after
 * three.js (r111, the global THREE) and its OrbitControls. The model comes in two
 * script elements: #histo-meta (JSON: buildings, attributes, years, the map, the palette) and
 * #histo-data (base64 of the gzip of the typed arrays, unpacked with the browser's
 * DecompressionStream: nothing is fetched). Coordinates: x east, y up, z south.
 *
 * window.histo is the page's hook for people and tests: ready, error, buildings,
 * drawn() (buildings drawn now), year, setYear(y), select(id), find(id),
 * screenPosition(id), view('top'|'oblique'), selected, firstFrameMs.
 */
(function () {
  "use strict";
  var PICKED = [255, 200, 0];
  var SHOWN = ["certainty", "roof_type", "roof_source", "eaves_height", "eaves_height_low", "eaves_height_high",
               "roof_height", "ridge_height_low", "ridge_height_high", "height_source", "source", "plot",
               "footprint", "map_year", "epochs", "dateOfConstruction",
               "dateOfConstructionEarliest", "dateOfConstructionLatest",
               "dateOfDemolitionEarliest", "dateOfDemolitionLatest", "standing", "conflict"];
  var hook = window.histo = {ready: false, error: null, selected: null, year: null};
  var start = performance.now();

  function fail(e) {
    hook.error = String(e && e.stack || e);
    document.getElementById("info").textContent = "The model could not be shown: " + e;
    throw e;
  }

  function unpack(meta) {
    var text = atob(document.getElementById("histo-data").textContent.trim());
    var bytes = new Uint8Array(text.length);
    for (var i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
    var stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("gzip"));
    return new Response(stream).arrayBuffer().then(function (buffer) {
      var out = {};
      meta.arrays.forEach(function (a) {
        var Type = {float32: Float32Array, uint8: Uint8Array, uint16: Uint16Array,
                    uint32: Uint32Array}[a.dtype];
        out[a.name] = new Type(buffer, a.offset, a.length);
      });
      return out;
    });
  }

  function main(meta, arrays) {
    var n = meta.ids.length, chunks = arrays.chunkStart.length - 1;
    // building id -> index: a Map, so that an id such as "__proto__" or "toString" is an
    // id like any other (in a plain object it would be the object's own machinery)
    var index = new Map();
    meta.ids.forEach(function (id, b) { index.set(id, b); });
    // every triangle's vertex indices, global (the file stores them per chunk)
    var all = new Uint32Array(arrays.triangles.length);
    for (var k = 0; k < chunks; k++) {
      for (var t = arrays.chunkStart[k] * 3; t < arrays.chunkStart[k + 1] * 3; t++) {
        all[t] = arrays.triangles[t] + (meta.localIndices ? arrays.chunkVertex[k] : 0);
      }
    }
    var colour = new Uint8Array(arrays.positions.length);
    function paint(k, rgb) {
      var b = arrays.chunkBuilding[k];
      for (var v = arrays.chunkVertex[k]; v < arrays.chunkVertex[k + 1]; v++) {
        var c = rgb || (meta.copied[b] ? meta.copiedColours : meta.colours)[arrays.kinds[v]];
        colour[3 * v] = c[0]; colour[3 * v + 1] = c[1]; colour[3 * v + 2] = c[2];
      }
    }
    for (k = 0; k < chunks; k++) paint(k, null);

    var geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(arrays.positions, 3));
    var colours = new THREE.BufferAttribute(colour, 3, true);
    geometry.setAttribute("color", colours);
    var material = new THREE.MeshPhongMaterial({vertexColors: THREE.VertexColors,
      flatShading: true, side: THREE.DoubleSide, shininess: 0});
    var mesh = new THREE.Mesh(geometry, material);
    mesh.rotation.x = -Math.PI / 2;           // model z up -> three.js y up
    var scene = new THREE.Scene();
    scene.background = new THREE.Color(meta.background[0] / 255, meta.background[1] / 255,
                                       meta.background[2] / 255);
    scene.add(mesh);
    scene.add(new THREE.HemisphereLight(0xffffff, 0x888888, 0.75));
    var sun = new THREE.DirectionalLight(0xffffff, 0.55);
    sun.position.set(-1, 2, 1.5);
    scene.add(sun);

    geometry.computeBoundingBox();
    var box = geometry.boundingBox, size = new THREE.Vector3();
    box.getSize(size);
    var centre = new THREE.Vector3((box.min.x + box.max.x) / 2, 0, -(box.min.y + box.max.y) / 2);
    var span = Math.max(size.x, size.y, 10);

    var plane = null;
    var canvas = document.getElementById("view");
    var renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true,
                                            preserveDrawingBuffer: true});
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    var camera = new THREE.PerspectiveCamera(40, 1, span / 1000, span * 20);
    var controls = new THREE.OrbitControls(camera, canvas);
    controls.target.copy(centre);
    controls.addEventListener("change", draw);
    hook.frames = 0;
    function draw() { renderer.render(scene, camera); hook.frames++; }
    function resize() {
      var w = canvas.clientWidth, h = canvas.clientHeight;
      renderer.setSize(w, h, false);
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
      draw();
    }
    hook.view = function (kind) {
      if (kind === "top") camera.position.set(centre.x, span * 1.6, centre.z + span * 1e-4);
      else camera.position.set(centre.x - span * 0.55, span * 0.75, centre.z + span * 0.95);
      controls.target.copy(centre);
      controls.update();
      draw();
    };

    // the buildings standing in the slider's year: their chunks' triangles in the index
    var drawnStart = [], drawnChunk = [];
    function show(year) {
      var on = [], total = 0;
      for (var k = 0; k < chunks; k++) {
        var spans = meta.chunkYears[k], keep = !spans.length;
        for (var s = 0; s < spans.length && !keep; s++) {
          keep = spans[s][0] <= year && year <= spans[s][1];
        }
        if (keep) { on.push(k); total += arrays.chunkStart[k + 1] - arrays.chunkStart[k]; }
      }
      var idx = new Uint32Array(total * 3), at = 0, seen = new Set();
      drawnStart = []; drawnChunk = [];
      on.forEach(function (k) {
        drawnStart.push(at / 3); drawnChunk.push(k);
        idx.set(all.subarray(arrays.chunkStart[k] * 3, arrays.chunkStart[k + 1] * 3), at);
        at += (arrays.chunkStart[k + 1] - arrays.chunkStart[k]) * 3;
        seen.add(arrays.chunkBuilding[k]);
      });
      geometry.setIndex(new THREE.BufferAttribute(idx, 1));
      hook.drawnBuildings = seen.size;
      hook.year = year;
      if (hook.selected !== null && !chunkOf(index.get(hook.selected))) select(null);
      draw();
    }
    hook.drawn = function () { return hook.drawnBuildings; };
    function chunkOf(b) {                       // the drawn chunk of building b
      for (var i = 0; i < drawnChunk.length; i++) {
        if (arrays.chunkBuilding[drawnChunk[i]] === b) return {k: drawnChunk[i], at: i};
      }
      return null;
    }

    var picked = null;
    var info = document.getElementById("info");
    function own(object, name) { return Object.prototype.hasOwnProperty.call(object, name); }
    function element(tag, text, className) {     // text only: the model's data never as HTML
      var e = document.createElement(tag);
      e.textContent = text;
      if (className) e.className = className;
      return e;
    }
    function select(id) {
      if (picked !== null) paint(picked, null);
      picked = null; hook.selected = null;
      info.textContent = "";
      if (id === null || !index.has(id)) {
        info.textContent = "Click a building to see what is known about it.";
      } else {
        var c = chunkOf(index.get(id));
        if (c) { picked = c.k; paint(c.k, PICKED); }
        hook.selected = id;
        var a = meta.attributes[index.get(id)];
        info.appendChild(element("b", id));
        SHOWN.concat(Object.keys(a).filter(function (x) { return SHOWN.indexOf(x) < 0; }))
          .forEach(function (name) {
            if (!own(a, name) || a[name] === null) return;
            var v = typeof a[name] === "object" ? JSON.stringify(a[name]) : String(a[name]);
            if (name === "certainty" && own(meta.certainty, v)) v += " (" + meta.certainty[v] + ")";
            var row = element("div");
            row.appendChild(element("span", name, "name"));
            row.appendChild(document.createTextNode(" " + v));
            info.appendChild(row);
          });
      }
      colours.needsUpdate = true;
      draw();
      return hook.selected;
    }
    hook.select = select;

    // a point on the building's largest roof triangle, in the page's pixels
    hook.screenPosition = function (id) {
      var c = index.has(id) ? chunkOf(index.get(id)) : null;
      if (!c) return null;
      var best = -1, point = null, p = arrays.positions;
      for (var t = arrays.chunkStart[c.k]; t < arrays.chunkStart[c.k + 1]; t++) {
        var i = all[3 * t], j = all[3 * t + 1], l = all[3 * t + 2];
        if (arrays.kinds[i] !== 2) continue;
        var ux = p[3 * j] - p[3 * i], uy = p[3 * j + 1] - p[3 * i + 1];
        var vx = p[3 * l] - p[3 * i], vy = p[3 * l + 1] - p[3 * i + 1];
        var area = Math.abs(ux * vy - uy * vx);
        if (area > best) {
          best = area;
          point = [0, 1, 2].map(function (d) { return (p[3 * i + d] + p[3 * j + d] + p[3 * l + d]) / 3; });
        }
      }
      if (!point) return null;
      var v = new THREE.Vector3(point[0], point[2], -point[1]).project(camera);
      var r = canvas.getBoundingClientRect();
      return [r.left + (v.x + 1) / 2 * r.width, r.top + (1 - v.y) / 2 * r.height];
    };

    var ray = new THREE.Raycaster(), down = null;
    canvas.addEventListener("pointerdown", function (e) { down = [e.clientX, e.clientY]; });
    canvas.addEventListener("pointerup", function (e) {
      if (!down || Math.abs(e.clientX - down[0]) + Math.abs(e.clientY - down[1]) > 4) return;
      var r = canvas.getBoundingClientRect();
      ray.setFromCamera(new THREE.Vector2((e.clientX - r.left) / r.width * 2 - 1,
                                          -(e.clientY - r.top) / r.height * 2 + 1), camera);
      var hit = ray.intersectObject(mesh)[0];
      if (!hit) { select(null); return; }
      var lo = 0, hi = drawnStart.length - 1;           // the drawn chunk of the triangle
      while (lo < hi) {
        var mid = (lo + hi + 1) >> 1;
        if (drawnStart[mid] <= hit.faceIndex) lo = mid; else hi = mid - 1;
      }
      select(meta.ids[arrays.chunkBuilding[drawnChunk[lo]]]);
    });

    var search = document.getElementById("search");
    hook.find = function (id) {
      if (!index.has(id) || !chunkOf(index.get(id))) return false;
      select(id);
      var c = chunkOf(index.get(id)), p = arrays.positions, v = arrays.chunkVertex;
      var x = 0, y = 0, m = v[c.k + 1] - v[c.k];
      for (var i = v[c.k]; i < v[c.k + 1]; i++) { x += p[3 * i]; y += p[3 * i + 1]; }
      controls.target.set(x / m, 0, -y / m);
      controls.update();
      draw();
      return true;
    };
    search.addEventListener("change", function () {
      if (!hook.find(search.value.trim())) info.textContent = "No building '" + search.value + "' here.";
    });

    var slider = document.getElementById("year");
    if (meta.years.length) {
      slider.min = meta.years[0]; slider.max = meta.years[1]; slider.value = meta.years[0];
      slider.addEventListener("input", function () {
        document.getElementById("year-label").textContent = slider.value;
        show(Number(slider.value));
      });
      document.getElementById("year-label").textContent = meta.years[0];
      hook.setYear = function (y) { slider.value = y; slider.dispatchEvent(new Event("input")); };
    } else {
      document.getElementById("time").style.display = "none";
      hook.setYear = function () { return false; };
    }
    hook.buildings = n;
    document.getElementById("title").textContent = meta.title;

    function finish() {
      window.addEventListener("resize", resize);
      show(meta.years.length ? meta.years[0] : 0);
      hook.view("oblique");
      resize();
      select(null);
      hook.firstFrameMs = performance.now() - start;
      hook.ready = true;
    }
    if (meta.map) {
      var m = meta.map, toggle = document.getElementById("map-toggle");
      new THREE.TextureLoader().load(m.png, function (texture) {
        texture.minFilter = THREE.LinearFilter;
        var west = m.extent[0], east = m.extent[1], south = m.extent[2], north = m.extent[3];
        plane = new THREE.Mesh(new THREE.PlaneGeometry(east - west, north - south),
                               new THREE.MeshBasicMaterial({map: texture}));
        plane.rotation.x = -Math.PI / 2;
        plane.position.set((west + east) / 2, -0.05, -(south + north) / 2);
        scene.add(plane);
        toggle.addEventListener("change", function () { plane.visible = toggle.checked; draw(); });
        finish();
      }, undefined, fail);
    } else {
      document.getElementById("map-row").style.display = "none";
      finish();
    }
  }

  try {
    var meta = JSON.parse(document.getElementById("histo-meta").textContent);
    unpack(meta).then(function (arrays) {
      try { main(meta, arrays); } catch (e) { fail(e); }
    }, fail);
  } catch (e) { fail(e); }
})();
