#!/usr/bin/env python3
"""A gearcam client written from proto/README.md alone: no Rust, only Zenoh and
MessagePack from PyPI (see requirements.txt).

    python3 client.py --connect tcp/127.0.0.1:7447 JOB.toml

submits the job to the planning station, follows its events to `delivered`,
reads the stored program back from the machine's agent and checks its SHA-256
against the receipt. With --refusals it also asks for what the services must
refuse and checks each typed refusal (code, field, got). Exit code 0 when
everything held, 1 otherwise (the reason on stderr). CI runs it against the
real services (tests/tests/python_client.rs).
"""

import argparse
import hashlib
import json
import queue
import sys
import time
import tomllib

import msgpack
import zenoh

PREFIX = "gearcam/v1"
SCHEMA = 1


def encode(kind, body):
    """A message in its envelope (MessagePack map with field names)."""
    return msgpack.packb({"schema": SCHEMA, "kind": kind, "body": body}, use_bin_type=True)


def decode(payload, kind):
    """The body of an envelope of the expected kind."""
    msg = msgpack.unpackb(payload, raw=False)
    if msg.get("schema") != SCHEMA:
        raise ValueError(f"schema {msg.get('schema')}, expected {SCHEMA}")
    if msg.get("kind") != kind:
        raise ValueError(f"kind {msg.get('kind')}, expected {kind}")
    return msg["body"]


def user_chunk(user):
    """A user's name as one key chunk, as gearcam writes it: what a chunk
    cannot hold (/ * $ ? #, control characters, a leading @) is _, a blank
    name is unknown."""
    chunk = "".join(
        "_" if c in "/*$?#" or ord(c) < 32 or ord(c) == 127 or (i == 0 and c == "@") else c
        for i, c in enumerate(user.strip()))
    return chunk or "unknown"


class Client:
    def __init__(self, endpoint):
        conf = zenoh.Config()
        conf.insert_json5("mode", '"client"')
        conf.insert_json5("connect/endpoints", json.dumps([endpoint]))
        conf.insert_json5("scouting/multicast/enabled", "false")
        self.session = zenoh.open(conf)

    def close(self):
        self.session.close()

    def query(self, key, kind, payload=None, timeout=10.0, attempts=5):
        """One reply of `kind` to a query; a query can find no queryable yet
        (a service still starting), so it is retried."""
        for attempt in range(attempts):
            replies = list(self.session.get(key, payload=payload, timeout=timeout))
            for reply in replies:
                if reply.ok is not None:
                    return decode(reply.ok.payload.to_bytes(), kind)
                raise RuntimeError(f"{key}: error reply {reply.err.payload.to_bytes()!r}")
            time.sleep(0.5)
        raise TimeoutError(f"{key}: no reply after {attempts} attempts")

    def wait_alive(self, services, timeout=60.0):
        """Waits for the services' liveliness tokens (gearcam/v1/alive/{service})."""
        deadline = time.monotonic() + timeout
        while True:
            alive = set()
            for reply in self.session.liveliness().get(f"{PREFIX}/alive/**", timeout=2.0):
                if reply.ok is not None:
                    alive.add(str(reply.ok.key_expr)[len(PREFIX) + len("/alive/"):])
            missing = [s for s in services if s not in alive]
            if not missing:
                return
            if time.monotonic() > deadline:
                raise TimeoutError(f"services not alive: {missing}")
            time.sleep(0.3)

    def submit(self, job_id, spec, by="python-client"):
        """Submits on the key of the user `by`: the station journals the
        key's user as the submitter (on a secure router, the login's)."""
        request = {
            "job_id": job_id,
            "submitted_at_ms": int(time.time() * 1000),
            "submitted_by": by,
            "spec": spec,
        }
        return self.query(f"{PREFIX}/station/submit/{user_chunk(by)}", "station_reply",
                          payload=encode("job_request", request))

    def follow(self, job_id):
        """A subscriber to the job's events and the queue they arrive in.
        Events are not replayed: subscribe before submitting; the status
        query catches up on what was missed."""
        events = queue.Queue()
        sub = self.session.declare_subscriber(
            f"{PREFIX}/jobs/{job_id}/events/*",
            lambda s: events.put(decode(s.payload.to_bytes(), "job_event")))
        return sub, events

    def status(self, job_id):
        return self.query(f"{PREFIX}/station/jobs/{job_id}", "station_reply")

    def store(self, machine, path, payload=None):
        return self.query(f"{PREFIX}/machines/{machine}/store/{path}", "store_reply", payload=payload)


def expect(cond, what):
    if not cond:
        raise AssertionError(what)
    print(f"ok: {what}")


def refused(reply, code, got=None):
    """The single typed error of a refusal, checked."""
    errors = reply.get("errors") or ([reply["error"]] if "error" in reply else [])
    expect(reply["type"] == "refused" and errors and errors[0]["code"] == code,
           f"refused with {code}: {reply}")
    if got is not None:
        expect(errors[0]["got"] == got, f"{code} names what was given ({got!r})")
    for f in ("stage", "field", "expected", "message"):
        expect(errors[0].get(f) not in (None, ""), f"{code} has its {f}")
    return errors[0]


def run(args):
    with open(args.job, "rb") as f:
        spec = tomllib.load(f)
    machine = spec["job"]["machine"]
    job_id = args.job_id
    c = Client(args.connect)
    try:
        c.wait_alive(["station", "knowledge", "model", "template", f"agent/{machine}"])
        sub, events = c.follow(job_id)
        reply = c.submit(job_id, spec)
        expect(reply["type"] == "accepted", f"{job_id} accepted: {reply['type']}")
        # A resubmission is the same job id and the same spec: a client's retry
        # with another time and sender is answered with the job's status.
        again = c.submit(job_id, spec, by="python-client-retry")
        expect(again["type"] == "accepted", "the same job id and spec again is accepted")
        seen, receipt = [], None
        deadline = time.monotonic() + 120
        while receipt is None:
            try:
                ev = events.get(timeout=max(0.1, deadline - time.monotonic()))
            except queue.Empty:
                raise TimeoutError(f"{job_id}: no delivery, events {seen}")
            kind = ev["event"]["type"]
            seen.append(kind)
            if kind == "failed":
                raise AssertionError(f"{job_id} failed: {ev['event']['errors']}")
            if kind == "delivered":
                receipt = ev["event"]["receipt"]
        sub.undeclare()
        expect(seen[0] == "accepted", f"the first event is accepted ({seen})")
        expect(all(k in seen for k in ("planned", "modelled", "programmed")),
               f"every stage reported ({seen})")
        status = c.status(job_id)
        expect(status["type"] == "status" and status["status"]["state"] == "delivered",
               "the station's status says delivered")
        # Read the program back from the machine's store and check its hash.
        name = receipt["name"]
        history = c.store(machine, f"programs/{name}")
        expect(history["type"] == "history", f"history of {name}")
        current = [v for v in history["history"]["versions"] if v["current"]]
        expect(len(current) == 1 and current[0]["sha256"] == receipt["sha256"],
               "the current version is the delivered one")
        version = c.store(machine, f"programs/{name}/versions/{current[0]['seq']}")
        expect(version["type"] == "version", "the version's text")
        text = version["program"]["text"]
        digest = hashlib.sha256(text.encode("utf-8")).hexdigest()
        expect(digest == receipt["sha256"], f"sha256 of the text read back = receipt ({digest[:12]})")
        print(f"delivered {job_id}: {receipt['file_name']} sha256 {digest}")

        if args.refusals:
            other = dict(spec, job=dict(spec["job"], quantity=spec["job"].get("quantity", 1) + 1))
            refused(c.submit(job_id, other), "JOB_ID_EXISTS", job_id)
            h99 = dict(spec, job=dict(spec["job"], machine="H99"))
            refused(c.submit(job_id + "-H99", h99), "UNKNOWN_MACHINE", "H99")
            refused(c.submit("bad id!", spec), "BAD_JOB_ID", "bad id!")
            refused(c.status("NO-SUCH-JOB"), "UNKNOWN_JOB", "NO-SUCH-JOB")
            refused(c.store(machine, "programs/NO_SUCH_PROGRAM"), "UNKNOWN_PROGRAM", "NO_SUCH_PROGRAM")
            refused(c.store(machine, f"programs/NO_SUCH_PROGRAM/versions/{current[0]['seq']}"),
                    "UNKNOWN_PROGRAM", "NO_SUCH_PROGRAM")
            refused(c.store(machine, f"programs/{name}/versions/999999"), "UNKNOWN_VERSION", "999999")
            refused(c.store(machine, f"changes/python-client/{name}"), "BAD_STORE_REQUEST", "no payload")
            rollback = encode("store_request", {"type": "rollback", "seq": 999999})
            refused(c.store(machine, f"changes/python-client/{name}", payload=rollback), "UNKNOWN_VERSION", "999999")
            # A known machine whose agent is not running: the job waits, and
            # says so in an event (and in its status).
            offline = args.offline_machine
            sub, events = c.follow(job_id + "-W")
            w = dict(spec, job=dict(spec["job"], machine=offline))
            expect(c.submit(job_id + "-W", w)["type"] == "accepted", f"a job for {offline} accepted")
            reason = None
            deadline = time.monotonic() + 30
            while reason is None and time.monotonic() < deadline:
                try:
                    ev = events.get(timeout=1.0)["event"]
                except queue.Empty:
                    continue
                if ev["type"] == "waiting":
                    reason = ev["reason"]
            sub.undeclare()
            expect(reason is not None and f"agent/{offline}" in reason,
                   f"a waiting event names the missing agent ({reason!r})")
            st = c.status(job_id + "-W")["status"]
            expect(st["state"] == "waiting" and f"agent/{offline}" in st.get("waiting_for", ""),
                   "the status says what it waits for")
        return 0
    finally:
        c.close()


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--connect", default="tcp/127.0.0.1:7447", help="a Zenoh router's endpoint")
    p.add_argument("--job-id", default=f"PY-{int(time.time())}", help="the job's id")
    p.add_argument("--refusals", action="store_true",
                   help="also check the typed refusals and a waiting job")
    p.add_argument("--offline-machine", default="H02",
                   help="a machine of the knowledge base whose agent is not running (with --refusals)")
    p.add_argument("job", help="a job file (TOML), e.g. examples/spur_840d.toml")
    args = p.parse_args()
    try:
        return run(args)
    except Exception as e:  # the reason, for a person or a test
        print(f"FAILED: {type(e).__name__}: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
