#!/usr/bin/env python3
"""Runs memid's measurement (examples/sizes.rs) and the SciPy peer (mem_peer.py) on the same
sizes in one run and prints, per size, the GEMM-bound lower bound and every time with its ratio.

    python3 benches/peer/compare.py          (needs python3 with numpy and scipy; cargo)
"""
import json
import pathlib
import subprocess
import sys

here = pathlib.Path(__file__).resolve().parent
root = here.parent.parent


def main():
    memid = json.loads(subprocess.run(
        ["cargo", "run", "--release", "-q", "-p", "memid-benches", "--example", "sizes"],
        cwd=root, check=True, capture_output=True, text=True).stdout)
    try:
        import numpy  # noqa: F401
        import scipy  # noqa: F401
        peer = json.loads(subprocess.run([sys.executable, str(here / "mem_peer.py")], check=True,
                                         capture_output=True, text=True).stdout)
    except Exception as e:  # noqa: BLE001
        print(f"SciPy peer not run ({e}); memid only")
        peer = None
    rate = memid["gemm_flops_per_s"]
    print(f"GEMM rate (faer, 1024³): {rate / 1e9:.1f} GFlop/s")
    print(f"{'size':<8} {'GFlop':>8} {'bound':>10} {'memid':>10} {'/bound':>7} {'numpy-vec':>10} {'ratio':>7} {'scipy':>10} {'ratio':>7}")
    for s in memid["sizes"]:
        name = s["size"]
        line = f"{name:<8} {s['flops'] / 1e9:>8.3f} {s['lower_bound_s'] * 1e3:>8.3f}ms {s['memid_s'] * 1e3:>8.3f}ms {s['memid_s'] / s['lower_bound_s']:>7.2f}"
        if peer:
            v, st = peer["sizes"][name]["vectorised"], peer["sizes"][name]["straightforward"]
            line += f" {v * 1e3:>8.3f}ms {v / s['memid_s']:>7.1f} {st * 1e3:>8.3f}ms {st / s['memid_s']:>7.1f}"
        print(line)
    fit = memid["paper_fit_s"]
    line = f"whole paper-size fit: memid {fit * 1e3:.3f} ms"
    if peer:
        line += f", numpy-vec {peer['paper_fit']['vectorised'] * 1e3:.2f} ms ({peer['paper_fit']['vectorised'] / fit:.0f}×), " \
                f"scipy {peer['paper_fit']['straightforward'] * 1e3:.2f} ms ({peer['paper_fit']['straightforward'] / fit:.0f}×)"
    print(line)
    par = memid["parallel"]
    print(f"two cores: large iteration {par['large_iteration_one_thread_s']:.3f} s → {par['large_iteration_two_threads_s']:.3f} s "
          f"({par['large_iteration_one_thread_s'] / par['large_iteration_two_threads_s']:.2f}×); two medium experiments "
          f"{par['medium_two_experiments_one_thread_s'] * 1e3:.2f} ms → {par['medium_two_experiments_two_threads_s'] * 1e3:.2f} ms "
          f"({par['medium_two_experiments_one_thread_s'] / par['medium_two_experiments_two_threads_s']:.2f}×)")
    (root / "target" / "peer-comparison.json").write_text(json.dumps({"memid": memid, "peer": peer}, indent=1))


if __name__ == "__main__":
    main()
