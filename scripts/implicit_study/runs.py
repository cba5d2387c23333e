"""One `mpm run` of the study: its command line, launching it (or reusing an earlier run's output) and what it
reported (summary.json, history.csv and the particle frames)."""
import hashlib
import json
import shutil
import statistics
import subprocess
import sys
import time

from mpm_output import read_history, read_pvd, read_vtp

from .paths import OUT, ROOT
from .progress import log

EXPLICIT = ["implicit.theta=0", "implicit.step_factor=1", "implicit.start_factor=1"]


class Run:
    """One `mpm run` and what it reported."""

    def __init__(self, problem, name, scene, sets, skipped=None, optional=False, time_limit=None):
        self.problem, self.name, self.scene, self.sets = problem, name, scene, list(sets)
        self.time_limit = time_limit   # seconds, on top of --timeout
        self.optional = optional   # an input error (exit 2) is reported as "rejected" instead of stopping the study
        self.dir = OUT / problem / name.replace(" ", "-")
        self.status = "skipped" if skipped else None
        self.skip_reason = skipped
        self.failure = ""
        self.summary = {}
        self.compute = None
        self.compute_key = None

    @property
    def ok(self):
        return self.status == "ok"

    @property
    def has_output(self):  # finished, failed, or stopped by --timeout after history.csv got its header line
        history = ROOT / self.dir / "history.csv"
        return self.status in ("ok", "failed") or (self.status == "timeout" and history.exists()
                                                   and history.stat().st_size > 0)

    def imp(self, key, default=0):
        return self.summary.get("implicit", {}).get(key, default)

    @property
    def steps(self):
        return self.summary.get("steps", 0)

    @property
    def evals(self):  # evaluation units: residual evaluations + steps (explicit: steps)
        return self.steps if self.imp("theta", 1.0) == 0 else self.imp("residual_evaluations") + self.steps

    @property
    def explicit_dt(self):
        return self.imp("explicit_dt", float("nan"))

    def factor(self, key, default):
        for s in self.sets:
            if s.startswith(f"implicit.{key}="):
                return float(s.split("=", 1)[1])
        return default

    @property
    def target_dt(self):
        return self.explicit_dt * (1.0 if self.imp("theta", 1.0) == 0 else self.factor("step_factor", 1.0))

    def command(self, args):
        cmd = [args.mpm, "run", str(self.scene), "--out", str(self.dir), "--quiet"]
        if args.threads:
            cmd += ["--threads", str(args.threads)]
        for s in self.sets:
            cmd += ["--set", s]
        return cmd

    def execute(self, args, repeat=1):
        if self.status == "skipped":
            log(f"{self.problem}/{self.name}: skipped ({self.skip_reason})")
            return self
        cmd = self.command(args)
        scene = hashlib.sha256((ROOT / self.scene).read_bytes()).hexdigest()  # a changed scene is a new run
        record = ROOT / self.dir / "study-run.json"
        if args.reuse and record.exists():
            saved = json.loads(record.read_text())
            if saved.get("scene_sha256") != scene:
                saved = {}
            if saved.get("command") == cmd and saved.get("status") == "timeout":
                self.status, self.failure = "timeout", saved["failure"]
                log(f"{self.problem}/{self.name}: reused {self.dir} ({self.describe()})")
                return self
            if saved.get("command") == cmd and (ROOT / self.dir / "summary.json").exists():
                self._load(saved)
                log(f"{self.problem}/{self.name}: reused {self.dir} ({self.describe()})")
                return self
        times = []
        for k in range(repeat):
            shutil.rmtree(ROOT / self.dir, ignore_errors=True)
            t0 = time.time()
            try:
                limit = min(t for t in (args.timeout, self.time_limit) if t) if args.timeout or self.time_limit else None
                proc = launch(cmd, limit)
            except subprocess.TimeoutExpired:
                self.status, self.failure = "timeout", f"stopped by the study after {limit:.0f} s"
                if self.has_output:
                    h = self.history()
                    if len(h["time"]):
                        self.failure += f" at t = {h['time'][-1]:.4g}, step {int(h['step'][-1])}"
                log(f"{self.problem}/{self.name}: TIMED OUT after {time.time() - t0:.0f} s")
                record.parent.mkdir(parents=True, exist_ok=True)
                record.write_text(json.dumps({"command": cmd, "scene_sha256": scene, "status": "timeout",
                                              "failure": self.failure}))
                return self
            summary_path = ROOT / self.dir / "summary.json"
            summary = json.loads(summary_path.read_text()) if summary_path.exists() else None
            if proc.returncode == 2 and self.optional:
                self.status, self.failure = "rejected", proc.stderr.strip().splitlines()[-1] if proc.stderr else ""
                log(f"{self.problem}/{self.name}: REJECTED by the binary: {self.failure}")
                return self
            if proc.returncode != 0 and not (proc.returncode == 1 and summary and summary.get("status") == "failed"):
                sys.stderr.write(proc.stdout + proc.stderr)
                raise SystemExit(f"implicit-study: `{' '.join(cmd)}` exited with status {proc.returncode}")
            self.summary = summary
            self.status = summary.get("status", "ok")
            self.failure = summary.get("failure", "")
            self.compute_key = "compute_seconds" if "compute_seconds" in summary else "wall_seconds"
            times.append(summary[self.compute_key])
            if not self.ok:
                break
        self.compute = statistics.median(times)
        (ROOT / self.dir / "study-run.json").write_text(json.dumps(
            {"command": cmd, "scene_sha256": scene, "compute": self.compute, "compute_key": self.compute_key,
             "repeats": len(times)}))
        log(f"{self.problem}/{self.name}: {self.describe()}")
        return self

    def _load(self, saved):
        self.summary = json.loads((ROOT / self.dir / "summary.json").read_text())
        self.status = self.summary.get("status", "ok")
        self.failure = self.summary.get("failure", "")
        self.compute, self.compute_key = saved["compute"], saved["compute_key"]

    def describe(self):
        if self.status != "ok":
            return f"{self.status.upper()}: {self.failure}"
        return (f"{self.steps} steps, {self.imp('newton_iterations')} Newton, {self.imp('krylov_iterations')} "
                f"GMRES, {self.imp('residual_evaluations')} residual evaluations, {self.compute:.3g} s")

    # outputs -------------------------------------------------------------------------------------------
    def history(self):
        return read_history(ROOT / self.dir / "history.csv")

    def newton_log(self):
        """newton.csv (runs with output.newton_log=on) as columns: step, attempt, dt, iteration, residual_norm."""
        return read_history(ROOT / self.dir / "newton.csv")

    def frames(self):
        """[(time, path)] from particles.pvd."""
        return read_pvd(ROOT / self.dir / "particles.pvd")

    def last_frame(self):
        return read_vtp(self.frames()[-1][1])


def launch(cmd, timeout):
    """subprocess.run, waiting up to two minutes while the binary is being relinked (not executable or busy)."""
    for attempt in range(25):
        try:
            return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=timeout or None)
        except (PermissionError, FileNotFoundError, OSError) as e:
            if isinstance(e, subprocess.TimeoutExpired) or attempt == 24:
                raise
            log(f"cannot start {cmd[0]} ({e}); retrying in 5 s")
            time.sleep(5)
