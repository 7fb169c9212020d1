"""Helpers of the Python checks under tests/.

small_scenes: the small scenes the model's checks simulate: the built-in
scene, and three shared scenes at 16x16 when ../shared/scenes is present.
A check that misses the shared scenes says SKIP and ends with finish(),
which makes ctest count it as skipped (exit 77, SKIP_RETURN_CODE); under
CI=true a missing ../shared/scenes is a failure.

json_diff: every difference between two JSON documents, keys in either;
provenance_diff: the provenance of two runs differs only in the keys varied."""
import os
import sys

SKIP_EXIT = 77

# The `paper` machine config fixes 16x16 ray groups (workload.group_size,
# workload.shadow_group_size); the checks' small scenes and traces have groups
# of their own, which these keys follow instead (0: the scene's or trace's).
FOLLOW_WORKLOAD = ["--set", "workload.group_size=0", "--set", "workload.shadow_group_size=0"]
_shared_missing = False


def in_ci():
    return os.environ.get("CI") == "true"


def shared_scenes_dir(root):
    return os.path.join(os.path.dirname(root), "shared", "scenes")


def need_shared(root):
    """True when the shared scenes are present; otherwise says SKIP (or, under
    CI=true, FAIL and exits 1) and returns False."""
    global _shared_missing
    shared = shared_scenes_dir(root)
    if os.path.isdir(shared):
        return True
    if in_ci():
        print(f"FAIL: {shared} is missing, and CI=true needs it")
        sys.exit(1)
    print(f"SKIP: {shared} is missing: the checks that need it did not run")
    _shared_missing = True
    return False


# The small scenes on which a run of the netlist takes seconds rather than
# tenths (the sports car: about 12 s at 16x16 on 5 ICCs, 25 times the event
# engine). Seeded grids whose subject is not the netlist run the event engine
# there; the netlist's share of them is checked on the other small scenes.
NETLIST_SLOW = frozenset({"sportscar"})


def engine_for(scene, mode):
    """sim.mode `mode` for a point of a grid on `scene` whose subject is not the netlist."""
    return "event" if mode == "netlist" and scene in NETLIST_SLOW else mode


def small_scenes(root):
    """(name, raplas arguments selecting it) for each small scene."""
    scenes = [("builtin", ["--set", "image.width=24", "--set", "image.height=24", "--set", "groups.size=8",
                           "--set", "groups.shadow_size=8", "--set", "builtin_detail=2"])]
    if need_shared(root):
        for name in ("cornell", "bunny_small", "sportscar"):
            scenes.append((name, ["--scene", os.path.join(root, "scenes", name + ".toml"), "--set", "image.width=16",
                                  "--set", "image.height=16"]))
    return scenes


def json_diff(a, b, skip=frozenset(), path=""):
    """Differences between JSON values a and b, as 'path: a != b' lines; keys
    in `skip` are left out at any depth."""
    if isinstance(a, dict) or isinstance(b, dict):
        if not (isinstance(a, dict) and isinstance(b, dict)):
            return [f"{path}: {a!r} != {b!r}"]
        keys = sorted(set(a) | set(b))
        return [d for k in keys if k not in skip for d in json_diff(a.get(k), b.get(k), skip, f"{path}/{k}")]
    if isinstance(a, list):
        if not isinstance(b, list) or len(a) != len(b):
            return [f"{path}: lengths differ"]
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in json_diff(x, y, skip, f"{path}[{i}]")]
    return [] if a == b else [f"{path}: {a!r} != {b!r}"]


# What a result says about where it comes from (docs/SWEEPS.md, "Provenance"):
# two runs of different configs differ here by design; provenance_diff checks it.
PROVENANCE = frozenset({"overrides", "config_hash", "resolved_config", "engine"})
# Keys that choose how a result is computed, not what it is: config_hash leaves
# them out (model::result_neutral_key), so runs that differ only in them have one hash.
RESULT_NEUTRAL = frozenset({"sim.mode", "sim.rtl", "sim.functional", "sim.sync_cycles", "sim.watchdog_cycles", "sim.cull"})


def provenance_diff(a, b, varied):
    """Differences between the provenance of runs a and b other than those of
    the config keys `varied`: their resolved configs must differ in exactly
    those keys, each named in both runs' overrides when it differs from the
    config, their config hashes differ exactly when some key does, and their
    workloads are the same."""
    ra, rb = a["resolved_config"], b["resolved_config"]
    differ = {k for k in set(ra) | set(rb) if ra.get(k) != rb.get(k)}
    d = [f"resolved_config: {k} differs ({ra.get(k)!r} != {rb.get(k)!r})" for k in sorted(differ - set(varied))]
    d += [f"resolved_config: {k} is the same in both runs" for k in sorted(set(varied) - differ)]
    counted = differ - RESULT_NEUTRAL
    if (a["config_hash"] != b["config_hash"]) != bool(counted):
        d.append(f"config_hash {a['config_hash']} vs {b['config_hash']} for {len(counted)} differing keys "
                 "that config_hash covers")
    if a["workload_hash"] != b["workload_hash"]:
        d.append(f"workload_hash {a['workload_hash']} != {b['workload_hash']}")
    for k in differ:
        for j in (a, b):
            if k in j["overrides"] and j["overrides"][k] != j["resolved_config"][k]:
                d.append(f"overrides: {k} = {j['overrides'][k]!r}, resolved {j['resolved_config'][k]!r}")
    return d


def report(name, cfg, differences, cycles):
    """Prints one grid point's line (its first differences if any); True if it failed."""
    if differences:
        print(f"FAIL {name} {' '.join(cfg)}:\n  " + "\n  ".join(differences[:8]))
        return True
    print(f"ok   {name} {' '.join(cfg)}: {cycles} cycles")
    return False


class Checks:
    """A test script's checks: `check(ok, what)` prints an ok/FAIL line and
    counts the failures; `check.finish()` exits as finish() does."""

    def __init__(self):
        self.failures = self.count = 0

    def __call__(self, ok, what):
        self.count += 1
        self.failures += not ok
        print(("ok   " if ok else "FAIL ") + what, flush=True)
        return ok

    def finish(self):
        print(f"{self.count - self.failures}/{self.count} checks passed")
        finish(self.failures)


def finish(failures):
    """Exit: 1 on failures, else 77 (skipped) when shared scenes were missing, else 0."""
    sys.exit(1 if failures else SKIP_EXIT if _shared_missing else 0)
