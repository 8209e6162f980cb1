// bigym teleop page: sends raw device events over a WebSocket, shows frames and status.
"use strict";

const state = {
  devices: [], connected: false, frames: [0, 0], status: null, sent: 0,
  held: new Set(), lastPad: "", latestScene: null, newScene: false,
};
const socket = new WebSocket(`ws://${location.host}/ws`);
socket.binaryType = "arraybuffer";
const $ = (id) => document.getElementById(id);
const objectUrls = [null, null];

function send(event) {
  if (socket.readyState !== WebSocket.OPEN) return false;
  socket.send(JSON.stringify(event));
  state.sent += 1;
  return true;
}

socket.onopen = () => { state.connected = true; $("connection").textContent = "online"; $("connection").className = ""; };
socket.onclose = () => {
  state.connected = false; $("connection").textContent = "offline (the server stopped)"; $("connection").className = "down";
};
socket.onmessage = (message) => {
  if (typeof message.data !== "string") return showFrame(new Uint8Array(message.data));
  const data = JSON.parse(message.data);
  if (data.type === "hello") return hello(data);
  if (data.type === "status") return showStatus(data);
  if (data.type === "error") $("errors").textContent = data.message;
};

function hello(data) {
  state.devices = data.devices;
  $("task").textContent = data.task;
  $("devices").textContent = "devices: " + data.devices.join(", ");
  const rows = state.devices.includes("keyboard") ? Object.entries(data.keys) : [];
  $("keys").innerHTML = rows.map(([k, v]) => `<tr><td>${k}</td><td>${v}</td></tr>`).join("");
  if (state.devices.includes("vr")) offerVR();
}

function showFrame(bytes) {
  const tag = bytes[0];
  const url = URL.createObjectURL(new Blob([bytes.subarray(1)], { type: "image/jpeg" }));
  const img = $(`view-${tag}`);
  if (!img) return;
  img.onload = () => { if (objectUrls[tag]) URL.revokeObjectURL(objectUrls[tag]); objectUrls[tag] = url; };
  img.src = url;
  state.frames[tag] += 1;
  if (tag === 0) { state.latestScene = img; state.newScene = true; }
}

function showStatus(s) {
  state.status = s;
  $("seed").textContent = s.seed;
  $("time").textContent = s.time.toFixed(1);
  $("success").textContent = s.success ? "yes" : "no";
  $("success").className = s.success ? "yes" : "";
  for (const key of ["kept", "rejected", "dropped"]) $(key).textContent = s[key];
  $("hands").textContent = s.active_hands.join(", ");
  $("grippers").textContent = s.grippers.map((g) => g.toFixed(2)).join(" / ");
  $("message").textContent = s.message;
  for (const line of s.outcomes) {
    const row = document.createElement("div");
    row.textContent = line;
    $("log").prepend(row);
  }
  if (s.errors.length) $("errors").textContent = s.errors.join("; ");
}

// ---------------------------------------------------------------- keyboard and mouse
const PAGE_KEYS = new Set(["Space", "Tab", "ArrowUp", "ArrowDown", "ArrowLeft", "ArrowRight", "PageUp", "PageDown",
  "Backspace", "Enter"]);
window.addEventListener("keydown", (e) => {
  if (!state.devices.includes("keyboard")) return;
  if (PAGE_KEYS.has(e.code)) e.preventDefault();
  if (e.repeat || state.held.has(e.code)) return;
  state.held.add(e.code);
  send({ type: "keydown", code: e.code });
});
window.addEventListener("keyup", (e) => {
  if (!state.devices.includes("keyboard") || !state.held.has(e.code)) return;
  state.held.delete(e.code);
  send({ type: "keyup", code: e.code });
});
window.addEventListener("blur", () => {  // a key released outside the page must not stay held
  for (const code of state.held) send({ type: "keyup", code });
  state.held.clear();
});
$("view-0").addEventListener("mousemove", (e) => {
  if (state.devices.includes("keyboard") && e.buttons & 1) {
    send({ type: "mousemove", dx: e.movementX, dy: e.movementY, buttons: e.buttons });
  }
});
$("view-0").addEventListener("wheel", (e) => {
  if (!state.devices.includes("keyboard")) return;
  e.preventDefault();
  send({ type: "wheel", dy: e.deltaY });
}, { passive: false });

for (const action of ["keep", "discard", "retry"]) {
  $(action).addEventListener("click", () => send({ type: "session", action }));
}

// ---------------------------------------------------------------- gamepad (Gamepad API, standard mapping)
function pollGamepad() {
  if (state.devices.includes("gamepad") && navigator.getGamepads) {
    const pad = [...navigator.getGamepads()].find((p) => p && p.mapping === "standard");
    if (pad) {
      const event = { type: "gamepad", axes: pad.axes.slice(0, 4), buttons: pad.buttons.map((b) => b.value) };
      const key = JSON.stringify(event);
      if (key !== state.lastPad) { state.lastPad = key; send(event); }
    }
  }
  requestAnimationFrame(pollGamepad);
}
requestAnimationFrame(pollGamepad);

// ---------------------------------------------------------------- VR (WebXR)
// Every XR frame the controllers' grip poses (local-floor space) and gamepads go out
// through xrFrame: the same function tests call with synthetic poses.
function xrFrame(controllers) {
  return send({ type: "xr", controllers });
}

async function offerVR() {
  if (!navigator.xr || !(await navigator.xr.isSessionSupported("immersive-vr"))) return;
  const button = $("enter-vr");
  button.hidden = false;
  button.onclick = () => navigator.xr.requestSession("immersive-vr", { requiredFeatures: ["local-floor"] }).then(runVR);
}

const VERTEX = `#version 300 es
in vec3 position; in vec2 uv; out vec2 texcoord; uniform mat4 projection, view;
void main() { texcoord = uv; gl_Position = projection * view * vec4(position, 1.0); }`;
const FRAGMENT = `#version 300 es
precision mediump float; in vec2 texcoord; out vec4 color; uniform sampler2D image;
void main() { color = texture(image, texcoord); }`;

function shader(gl, kind, source) {
  const s = gl.createShader(kind);
  gl.shaderSource(s, source);
  gl.compileShader(s);
  return s;
}

async function runVR(session) {
  const canvas = document.createElement("canvas");
  const gl = canvas.getContext("webgl2", { xrCompatible: true });
  const program = gl.createProgram();
  gl.attachShader(program, shader(gl, gl.VERTEX_SHADER, VERTEX));
  gl.attachShader(program, shader(gl, gl.FRAGMENT_SHADER, FRAGMENT));
  gl.linkProgram(program);
  // the scene view on a 1.6 m x 1.2 m screen, 2 m ahead, its centre 1.4 m above the floor
  const quad = new Float32Array([-0.8, 0.8, -2, 0, 1, 0.8, 0.8, -2, 1, 1, -0.8, 2.0, -2, 0, 0, 0.8, 2.0, -2, 1, 0]);
  const buffer = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  gl.bufferData(gl.ARRAY_BUFFER, quad, gl.STATIC_DRAW);
  const texture = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, texture);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  const layer = new XRWebGLLayer(session, gl);
  session.updateRenderState({ baseLayer: layer });
  const space = await session.requestReferenceSpace("local-floor");
  const where = (name) => gl.getUniformLocation(program, name);

  function onFrame(time, frame) {
    session.requestAnimationFrame(onFrame);
    const controllers = [];
    for (const source of session.inputSources) {
      if (!source.gripSpace || !source.gamepad || !["left", "right"].includes(source.handedness)) continue;
      const pose = frame.getPose(source.gripSpace, space);
      const c = { hand: source.handedness, buttons: source.gamepad.buttons.map((b) => b.value), axes: [...source.gamepad.axes] };
      if (pose) {
        const p = pose.transform.position, o = pose.transform.orientation;
        c.position = [p.x, p.y, p.z];
        c.orientation = [o.x, o.y, o.z, o.w];
      }
      controllers.push(c);
    }
    if (controllers.length) xrFrame(controllers);
    const viewer = frame.getViewerPose(space);
    if (!viewer) return;
    gl.bindFramebuffer(gl.FRAMEBUFFER, layer.framebuffer);
    gl.clearColor(0.1, 0.1, 0.12, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.useProgram(program);
    gl.bindTexture(gl.TEXTURE_2D, texture);
    if (state.newScene && state.latestScene && state.latestScene.complete) {
      gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB, gl.RGB, gl.UNSIGNED_BYTE, state.latestScene);
      state.newScene = false;
    }
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    const position = gl.getAttribLocation(program, "position"), uv = gl.getAttribLocation(program, "uv");
    gl.enableVertexAttribArray(position);
    gl.vertexAttribPointer(position, 3, gl.FLOAT, false, 20, 0);
    gl.enableVertexAttribArray(uv);
    gl.vertexAttribPointer(uv, 2, gl.FLOAT, false, 20, 12);
    for (const view of viewer.views) {
      const v = layer.getViewport(view);
      gl.viewport(v.x, v.y, v.width, v.height);
      gl.uniformMatrix4fv(where("projection"), false, view.projectionMatrix);
      gl.uniformMatrix4fv(where("view"), false, view.transform.inverse.matrix);
      gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    }
  }
  session.requestAnimationFrame(onFrame);
}

window.bigymTeleop = { send, xrFrame, state };
