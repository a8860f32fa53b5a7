// gearcam's page script: additions to pages that work without it. Every
// value from the server is put into the page as text (textContent), never
// as HTML.
"use strict";

// A job's page: its state and progress as the events arrive; at the end
// the page is loaded again to show the program or the errors, with the
// progress seen so far kept for the page (session storage).
function followJob(status) {
  const state = document.getElementById("state");
  const progress = document.getElementById("progress");
  const key = "gearcam-progress-" + status.dataset.job;
  const seen = JSON.parse(sessionStorage.getItem(key) || "[]");
  const show = (line) => {
    const li = document.createElement("li");
    li.textContent = line;
    progress.appendChild(li);
  };
  seen.forEach(show);
  if (status.dataset.final) return;
  const source = new EventSource(status.dataset.events);
  source.addEventListener("job", (e) => {
    const ev = JSON.parse(e.data);
    state.textContent = ev.state;
    const line = new Date(ev.at_ms).toISOString().replace("T", " ").slice(0, 19) + " " + ev.text;
    seen.push(line);
    sessionStorage.setItem(key, JSON.stringify(seen));
    show(line);
    if (["delivered", "failed", "superseded", "cancelled"].includes(ev.state)) {
      source.close();
      setTimeout(() => window.location.reload(), 300);
    }
  });
}

// The queue: each row's state as its job's events arrive; a new job is
// added at the top.
function followQueue(tbody) {
  const source = new EventSource(tbody.dataset.events);
  source.addEventListener("job", (e) => {
    const ev = JSON.parse(e.data);
    let row = null;
    for (const tr of tbody.querySelectorAll("tr[data-job]")) {
      if (tr.dataset.job === ev.job) row = tr;
    }
    if (!row) {
      row = document.createElement("tr");
      row.dataset.job = ev.job;
      const a = document.createElement("a");
      a.href = "/jobs/" + encodeURIComponent(ev.job);
      a.textContent = ev.job;
      // job, part number, parts, machine, state, updated: the page shows
      // the rest when it is loaded again.
      const cells = [a, "", "", "", "", ""].map((c) => {
        const td = document.createElement("td");
        if (typeof c === "string") td.textContent = c; else td.appendChild(c);
        return td;
      });
      cells[4].className = "state";
      cells.forEach((td) => row.appendChild(td));
      tbody.insertBefore(row, tbody.firstChild);
    }
    row.className = ev.state;
    row.querySelector("td.state").textContent = ev.state;
  });
}

// A job's form: the check while typing (the server's check, shown beside
// the fields it names), a moment after the last key.
function checkWhileTyping(form) {
  let timer = null;
  let asked = 0;
  const run = async () => {
    const mine = ++asked;
    const body = new URLSearchParams(new FormData(form));
    const reply = await fetch(form.dataset.check, { method: "POST", body });
    if (!reply.ok || mine !== asked) return;
    const checked = await reply.json();
    for (const p of form.querySelectorAll("p.field")) {
      const name = p.dataset.field;
      const errors = checked.errors.filter((e) => e.field === name);
      p.querySelector(".field-error").textContent = errors
        .map((e) => e.code + ": expected " + e.expected + ", got " + e.got + ". ")
        .join("");
      const proposal = checked.proposals.find((x) => x.field === name);
      p.querySelector(".proposal").textContent = proposal
        ? "proposed " + Number(proposal.value.toFixed(4)) + " from " + proposal.source
        : "";
    }
    const summary = document.getElementById("summary");
    const placed = new Set([...form.querySelectorAll("p.field")].map((p) => p.dataset.field));
    const others = checked.errors.filter((e) => !placed.has(e.field));
    summary.textContent = "";
    const verdict = document.createElement("p");
    verdict.className = checked.errors.length ? "refused" : "ok";
    verdict.textContent = checked.errors.length
      ? checked.errors.length + " error(s): the job would be refused."
      : "The job passes every check here.";
    summary.appendChild(verdict);
    for (const e of others) {
      const line = document.createElement("p");
      line.className = "field-error";
      line.textContent = e.code + " " + e.field + ": expected " + e.expected + ", got " + e.got + ". " + e.message;
      summary.appendChild(line);
    }
  };
  form.addEventListener("input", () => {
    clearTimeout(timer);
    timer = setTimeout(run, 250);
  });
}

document.addEventListener("DOMContentLoaded", () => {
  const status = document.getElementById("status");
  if (status && status.dataset.events) followJob(status);
  const jobs = document.getElementById("jobs");
  if (jobs && jobs.dataset.events) followQueue(jobs);
  const form = document.getElementById("job");
  if (form && form.dataset.check) checkWhileTyping(form);
});
