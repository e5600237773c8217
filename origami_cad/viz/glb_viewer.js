/* origami_cad's offline glb viewer (WebGL 1, no library, no network).
 *
 * Shows every <figure class="oc-view"> of the page: the base64 glb in its
 * <script type="application/octet-stream" class="oc-glb">, drawn in its <canvas>.
 * It reads the glb files origami_cad writes (origami_cad/viz/gltf.py): one root
 * node over meshes in mm with z up, triangles or lines, one base colour each,
 * morph targets played by a "weights" animation. Drag to turn, wheel to zoom,
 * double-click to reset; an animated view has a play button and a slider.
 *
 * For tests: <html data-errors> counts uncaught errors and console.error calls;
 * each figure gets data-rendered="ok" once its first frame has ink on the canvas
 * (data-pixels: how many pixels differ from the background), and <html
 * data-views-rendered> counts those figures.
 */
(function () {
  "use strict";
  var root = document.documentElement;
  if (window.ocGlbViewer) {
    window.ocGlbViewer();  // loaded before (a notebook's earlier output): start new figures
    return;
  }
  var errors = 0;
  function noteError() {
    errors += 1;
    root.setAttribute("data-errors", String(errors));
  }
  root.setAttribute("data-errors", "0");
  window.addEventListener("error", noteError);
  var consoleError = console.error;
  console.error = function () {
    noteError();
    return consoleError.apply(console, arguments);
  };

  var TYPES = { 5126: Float32Array, 5123: Uint16Array, 5125: Uint32Array };
  var WIDTH = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 };
  var BACKGROUND = [1, 1, 1];

  function decodeBase64(text) {
    var s = atob(text.replace(/\s+/g, ""));
    var out = new Uint8Array(s.length);
    for (var i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
    return out.buffer;
  }

  function parseGlb(buffer) {
    var dv = new DataView(buffer);
    if (dv.getUint32(0, true) !== 0x46546c67) throw new Error("not a glb file");
    var jsonLength = dv.getUint32(12, true);
    var json = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 20, jsonLength)));
    var binHead = 20 + jsonLength;
    var bin = null;
    if (binHead + 8 <= buffer.byteLength) {
      var binLength = dv.getUint32(binHead, true);
      bin = buffer.slice(binHead + 8, binHead + 8 + binLength);
    }
    return { json: json, bin: bin };
  }

  function accessor(glb, index) {
    var a = glb.json.accessors[index];
    var v = glb.json.bufferViews[a.bufferView];
    var Type = TYPES[a.componentType];
    if (!Type) throw new Error("unsupported component type " + a.componentType);
    var offset = (v.byteOffset || 0) + (a.byteOffset || 0);
    return new Type(glb.bin, offset, a.count * WIDTH[a.type]);
  }

  /* The drawables of a glb: positions, targets, indices, colour, mode, animation. */
  function readModel(glb) {
    var json = glb.json;
    var items = [];
    var byNode = {};
    (json.nodes || []).forEach(function (node, n) {
      if (node.mesh === undefined) return;
      json.meshes[node.mesh].primitives.forEach(function (prim) {
        var mat = json.materials && prim.material !== undefined ? json.materials[prim.material] : {};
        var pbr = mat.pbrMetallicRoughness || {};
        var item = {
          name: node.name || "",
          base: accessor(glb, prim.attributes.POSITION),
          targets: (prim.targets || []).map(function (t) { return accessor(glb, t.POSITION); }),
          indices: prim.indices !== undefined ? accessor(glb, prim.indices) : null,
          mode: prim.mode === undefined ? 4 : prim.mode,
          color: (pbr.baseColorFactor || [0.8, 0.8, 0.8, 1]).slice(0, 3),
          weights: null,
        };
        items.push(item);
        byNode[n] = (byNode[n] || []).concat([item]);
      });
    });
    var anim = null;
    if (json.animations && json.animations.length) {
      var a = json.animations[0];
      a.channels.forEach(function (ch) {
        if (ch.target.path !== "weights") return;
        var s = a.samplers[ch.sampler];
        var times = accessor(glb, s.input);
        var values = accessor(glb, s.output);
        anim = anim || { times: times, duration: times[times.length - 1] };
        (byNode[ch.target.node] || []).forEach(function (item) { item.weights = values; });
      });
    }
    return { items: items, animation: anim };
  }

  /* Positions of an item at time t (seconds): base + sum of weighted targets. */
  function positionsAt(item, anim, t) {
    if (!anim || !item.weights || !item.targets.length) return item.base;
    var times = anim.times;
    var n = item.targets.length;
    var k = 0;
    while (k < times.length - 2 && t >= times[k + 1]) k += 1;
    var span = times[k + 1] - times[k];
    var f = span > 0 ? Math.min(Math.max((t - times[k]) / span, 0), 1) : 0;
    var out = new Float32Array(item.base);
    for (var j = 0; j < n; j++) {
      var w = (1 - f) * item.weights[k * n + j] + f * item.weights[(k + 1) * n + j];
      if (w === 0) continue;
      var d = item.targets[j];
      for (var i = 0; i < out.length; i++) out[i] += w * d[i];
    }
    return out;
  }

  /* Un-indexed vertex (and, for triangles, flat normal) arrays of an item. */
  function expand(item, pos) {
    var per = item.mode === 4 ? 3 : 2;
    var idx = item.indices;
    var count = idx ? idx.length : pos.length / 3;
    var p = new Float32Array(count * 3);
    for (var i = 0; i < count; i++) {
      var v = idx ? idx[i] : i;
      p[3 * i] = pos[3 * v];
      p[3 * i + 1] = pos[3 * v + 1];
      p[3 * i + 2] = pos[3 * v + 2];
    }
    var nrm = null;
    if (per === 3) {
      nrm = new Float32Array(count * 3);
      for (var t = 0; t + 2 < count; t += 3) {
        var ax = p[3 * t + 3] - p[3 * t], ay = p[3 * t + 4] - p[3 * t + 1], az = p[3 * t + 5] - p[3 * t + 2];
        var bx = p[3 * t + 6] - p[3 * t], by = p[3 * t + 7] - p[3 * t + 1], bz = p[3 * t + 8] - p[3 * t + 2];
        var nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
        var len = Math.sqrt(nx * nx + ny * ny + nz * nz) || 1;
        for (var c = 0; c < 3; c++) {
          nrm[3 * (t + c)] = nx / len;
          nrm[3 * (t + c) + 1] = ny / len;
          nrm[3 * (t + c) + 2] = nz / len;
        }
      }
    }
    return { p: p, n: nrm, count: count };
  }

  function bounds(model) {
    var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    model.items.forEach(function (item) {
      [item.base].concat(item.targets.map(function (d) {
        var q = new Float32Array(item.base);
        for (var i = 0; i < q.length; i++) q[i] += d[i];
        return q;
      })).forEach(function (pos) {
        for (var i = 0; i < pos.length; i += 3) {
          for (var c = 0; c < 3; c++) {
            lo[c] = Math.min(lo[c], pos[i + c]);
            hi[c] = Math.max(hi[c], pos[i + c]);
          }
        }
      });
    });
    if (!isFinite(lo[0])) return { center: [0, 0, 0], radius: 1 };
    var center = [0, 1, 2].map(function (c) { return (lo[c] + hi[c]) / 2; });
    var r = Math.sqrt([0, 1, 2].reduce(function (s, c) { return s + Math.pow(hi[c] - lo[c], 2); }, 0)) / 2;
    return { center: center, radius: r || 1 };
  }

  function perspective(fovy, aspect, near, far) {
    var f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
    return [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0];
  }

  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function norm(a) { var l = Math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) || 1; return [a[0] / l, a[1] / l, a[2] / l]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

  function lookAt(eye, center, up) {
    var z = norm(sub(eye, center)), x = norm(cross(up, z)), y = cross(z, x);
    return [x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
      -dot(x, eye), -dot(y, eye), -dot(z, eye), 1];
  }

  function multiply(a, b) {
    var out = new Array(16);
    for (var c = 0; c < 4; c++) {
      for (var r = 0; r < 4; r++) {
        var s = 0;
        for (var k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
        out[c * 4 + r] = s;
      }
    }
    return out;
  }

  var VERTEX = "attribute vec3 p; attribute vec3 n; uniform mat4 mvp; varying vec3 vn;" +
    "void main(){ vn = n; gl_Position = mvp * vec4(p, 1.0); }";
  var FRAGMENT = "precision mediump float; varying vec3 vn; uniform vec3 color; uniform vec3 light;" +
    "uniform float lit; void main(){ float s = 1.0;" +
    " if (lit > 0.5) { s = 0.35 + 0.65 * abs(dot(normalize(vn), light)); }" +
    " gl_FragColor = vec4(pow(color * s, vec3(1.0 / 2.2)), 1.0); }";

  function compile(gl, type, source) {
    var s = gl.createShader(type);
    gl.shaderSource(s, source);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  }

  function program(gl) {
    var prog = gl.createProgram();
    gl.attachShader(prog, compile(gl, gl.VERTEX_SHADER, VERTEX));
    gl.attachShader(prog, compile(gl, gl.FRAGMENT_SHADER, FRAGMENT));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
    return prog;
  }

  function View(figure) {
    var canvas = figure.querySelector("canvas");
    var source = figure.querySelector("script.oc-glb");
    this.figure = figure;
    this.canvas = canvas;
    this.model = readModel(parseGlb(decodeBase64(source.textContent)));
    this.box = bounds(this.model);
    var gl = canvas.getContext("webgl", { antialias: true, preserveDrawingBuffer: true });
    if (!gl) {
      figure.setAttribute("data-rendered", "no-webgl");
      canvas.insertAdjacentHTML("afterend", "<p>This browser has no WebGL: the 3D view cannot be shown.</p>");
      return;
    }
    this.gl = gl;
    this.prog = program(gl);
    this.loc = {
      p: gl.getAttribLocation(this.prog, "p"), n: gl.getAttribLocation(this.prog, "n"),
      mvp: gl.getUniformLocation(this.prog, "mvp"), color: gl.getUniformLocation(this.prog, "color"),
      light: gl.getUniformLocation(this.prog, "light"), lit: gl.getUniformLocation(this.prog, "lit"),
    };
    this.buffers = this.model.items.map(function () { return { p: gl.createBuffer(), n: gl.createBuffer(), count: 0 }; });
    this.reset();
    this.time = 0;
    this.playing = !!this.model.animation;
    this.upload(0);
    this.controls();
    this.draw();
    this.check();
    if (this.model.animation) this.loop();
  }

  View.prototype.reset = function () {
    this.yaw = -Math.PI / 3;
    this.pitch = Math.PI / 5;
    this.zoom = 1;
  };

  View.prototype.upload = function (t) {
    var gl = this.gl, anim = this.model.animation;
    this.model.items.forEach(function (item, k) {
      var b = this.buffers[k];
      if (b.count && !(anim && item.weights)) return; // static: uploaded once
      var data = expand(item, positionsAt(item, anim, t));
      gl.bindBuffer(gl.ARRAY_BUFFER, b.p);
      gl.bufferData(gl.ARRAY_BUFFER, data.p, gl.DYNAMIC_DRAW);
      if (data.n) {
        gl.bindBuffer(gl.ARRAY_BUFFER, b.n);
        gl.bufferData(gl.ARRAY_BUFFER, data.n, gl.DYNAMIC_DRAW);
      }
      b.count = data.count;
      b.lit = !!data.n;
    }, this);
  };

  View.prototype.draw = function () {
    var gl = this.gl, loc = this.loc, box = this.box, canvas = this.canvas;
    var dist = 2.6 * box.radius / this.zoom;
    var cp = Math.cos(this.pitch);
    var dir = [cp * Math.cos(this.yaw), cp * Math.sin(this.yaw), Math.sin(this.pitch)];
    var eye = [0, 1, 2].map(function (c) { return box.center[c] + dist * dir[c]; });
    var view = lookAt(eye, box.center, [0, 0, 1]);
    var proj = perspective(Math.PI / 4, canvas.width / canvas.height, dist / 100, dist + 4 * box.radius);
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.clearColor(BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.enable(gl.POLYGON_OFFSET_FILL);
    gl.polygonOffset(1, 1);
    gl.useProgram(this.prog);
    gl.uniformMatrix4fv(loc.mvp, false, new Float32Array(multiply(proj, view)));
    gl.uniform3fv(loc.light, new Float32Array(dir));
    this.model.items.forEach(function (item, k) {
      var b = this.buffers[k];
      if (!b.count) return;
      gl.bindBuffer(gl.ARRAY_BUFFER, b.p);
      gl.enableVertexAttribArray(loc.p);
      gl.vertexAttribPointer(loc.p, 3, gl.FLOAT, false, 0, 0);
      if (b.lit && loc.n >= 0) {
        gl.bindBuffer(gl.ARRAY_BUFFER, b.n);
        gl.enableVertexAttribArray(loc.n);
        gl.vertexAttribPointer(loc.n, 3, gl.FLOAT, false, 0, 0);
      } else if (loc.n >= 0) {
        gl.disableVertexAttribArray(loc.n);
        gl.vertexAttrib3f(loc.n, 0, 0, 1);
      }
      gl.uniform3fv(loc.color, new Float32Array(item.color));
      gl.uniform1f(loc.lit, b.lit ? 1 : 0);
      gl.drawArrays(item.mode === 4 ? gl.TRIANGLES : gl.LINES, 0, b.count);
    }, this);
  };

  /* Count the pixels of the first frame that differ from the background. */
  View.prototype.check = function () {
    var gl = this.gl, w = this.canvas.width, h = this.canvas.height;
    var px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    var ink = 0;
    for (var i = 0; i < px.length; i += 4) {
      if (Math.abs(px[i] - 255) + Math.abs(px[i + 1] - 255) + Math.abs(px[i + 2] - 255) > 24) ink += 1;
    }
    this.figure.setAttribute("data-pixels", String(ink));
    this.figure.setAttribute("data-rendered", ink > 0 ? "ok" : "blank");
    if (ink > 0) {
      var done = Number(root.getAttribute("data-views-rendered") || "0") + 1;
      root.setAttribute("data-views-rendered", String(done));
    }
  };

  View.prototype.loop = function () {
    var self = this, last = null;
    function frame(now) {
      if (last !== null && self.playing) {
        self.time = (self.time + (now - last) / 1000) % (self.model.animation.duration * 1.25);
        self.show(Math.min(self.time, self.model.animation.duration));
      }
      last = now;
      window.requestAnimationFrame(frame);
    }
    window.requestAnimationFrame(frame);
  };

  View.prototype.show = function (t) {
    this.upload(t);
    this.draw();
    if (this.slider) this.slider.value = String(t / this.model.animation.duration);
  };

  View.prototype.controls = function () {
    var self = this, canvas = this.canvas, drag = null;
    canvas.addEventListener("pointerdown", function (e) {
      drag = [e.clientX, e.clientY];
      if (canvas.setPointerCapture) canvas.setPointerCapture(e.pointerId);
    });
    canvas.addEventListener("pointermove", function (e) {
      if (!drag) return;
      self.yaw -= (e.clientX - drag[0]) * 0.01;
      self.pitch = Math.max(-1.55, Math.min(1.55, self.pitch + (e.clientY - drag[1]) * 0.01));
      drag = [e.clientX, e.clientY];
      self.draw();
    });
    canvas.addEventListener("pointerup", function () { drag = null; });
    canvas.addEventListener("wheel", function (e) {
      e.preventDefault();
      self.zoom = Math.max(0.2, Math.min(20, self.zoom * Math.exp(-e.deltaY * 0.001)));
      self.draw();
    }, { passive: false });
    canvas.addEventListener("dblclick", function () { self.reset(); self.draw(); });
    if (!this.model.animation) return;
    var bar = document.createElement("div");
    bar.className = "oc-controls";
    var button = document.createElement("button");
    button.type = "button";
    button.textContent = "pause";
    var slider = document.createElement("input");
    slider.type = "range";
    slider.min = "0";
    slider.max = "1";
    slider.step = "0.001";
    slider.value = "0";
    button.addEventListener("click", function () {
      self.playing = !self.playing;
      button.textContent = self.playing ? "pause" : "play";
    });
    slider.addEventListener("input", function () {
      self.playing = false;
      button.textContent = "play";
      self.time = Number(slider.value) * self.model.animation.duration;
      self.show(self.time);
    });
    bar.appendChild(button);
    bar.appendChild(slider);
    canvas.insertAdjacentElement("afterend", bar);
    this.slider = slider;
  };

  function start() {
    var figures = document.querySelectorAll("figure.oc-view");
    for (var i = 0; i < figures.length; i++) {
      // a notebook runs this script once per output: each figure is started once
      if (figures[i].hasAttribute("data-oc-started")) continue;
      figures[i].setAttribute("data-oc-started", "");
      try {
        new View(figures[i]);
      } catch (err) {
        figures[i].setAttribute("data-rendered", "error");
        console.error("3D view " + i + ": " + (err && err.message ? err.message : err));
      }
    }
    root.setAttribute("data-views", String(figures.length));
  }

  window.ocGlbViewer = start;
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start);
  else start();
})();
