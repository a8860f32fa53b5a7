// gearcam's pictures: zoom and pan of each `.zoomable` picture. The wheel
// zooms about the pointer, the buttons about the middle, dragging pans,
// Reset shows the whole picture again. The picture is moved by a CSS
// transform on it (`translate(x, y) scale(s)`, its origin at its top left);
// the box keeps its size. Without this script the picture is simply shown.
"use strict";

function zoomable(box) {
  const picture = box.querySelector("img, object, svg");
  if (!picture) return;
  let scale = 1;
  let x = 0;
  let y = 0;
  const apply = () => {
    picture.style.transform = "translate(" + x + "px, " + y + "px) scale(" + scale + ")";
    box.dataset.zoom = scale.toFixed(3);
  };
  // Zooms by `factor` about the point (px, py) of the box: that point of
  // the picture stays where it is.
  const zoomAt = (factor, px, py) => {
    const next = Math.min(40, Math.max(0.25, scale * factor));
    const f = next / scale;
    x = px - f * (px - x);
    y = py - f * (py - y);
    scale = next;
    apply();
  };
  const reset = () => {
    scale = 1;
    x = 0;
    y = 0;
    apply();
  };
  box.style.overflow = "hidden";
  box.style.cursor = "grab";
  box.style.touchAction = "none";
  picture.style.transformOrigin = "0 0";
  picture.draggable = false;

  const tools = document.createElement("div");
  tools.className = "zoom-tools";
  const button = (cls, text, title, act) => {
    const b = document.createElement("button");
    b.type = "button";
    b.className = cls;
    b.textContent = text;
    b.title = title;
    b.addEventListener("click", act);
    tools.appendChild(b);
  };
  const middle = (factor) => () => zoomAt(factor, box.clientWidth / 2, box.clientHeight / 2);
  button("zoom-in", "+", "Zoom in", middle(1.25));
  button("zoom-out", "\u2212", "Zoom out", middle(1 / 1.25));
  button("zoom-reset", "Reset", "The whole picture", reset);
  const hint = document.createElement("span");
  hint.textContent = " wheel to zoom, drag to move";
  tools.appendChild(hint);
  box.parentNode.insertBefore(tools, box);

  box.addEventListener("wheel", (e) => {
    e.preventDefault();
    const r = box.getBoundingClientRect();
    zoomAt(e.deltaY < 0 ? 1.15 : 1 / 1.15, e.clientX - r.left, e.clientY - r.top);
  }, { passive: false });
  let drag = null;
  box.addEventListener("pointerdown", (e) => {
    drag = { id: e.pointerId, sx: e.clientX, sy: e.clientY, x, y };
    box.setPointerCapture(e.pointerId);
    box.style.cursor = "grabbing";
  });
  box.addEventListener("pointermove", (e) => {
    if (!drag || drag.id !== e.pointerId) return;
    x = drag.x + e.clientX - drag.sx;
    y = drag.y + e.clientY - drag.sy;
    apply();
  });
  const stop = () => {
    drag = null;
    box.style.cursor = "grab";
  };
  box.addEventListener("pointerup", stop);
  box.addEventListener("pointercancel", stop);
  box.addEventListener("dblclick", reset);

  // A picture the page cannot have (no model yet): say so instead.
  picture.addEventListener("error", () => {
    const note = document.createElement("p");
    note.className = "no-picture";
    note.textContent = picture.alt || "No picture.";
    tools.remove();
    box.replaceWith(note);
  });
  apply();
}

function zoomables() {
  document.querySelectorAll(".zoomable").forEach(zoomable);
}

if (document.readyState === "loading") {
  document.addEventListener("DOMContentLoaded", zoomables);
} else {
  zoomables();
}
