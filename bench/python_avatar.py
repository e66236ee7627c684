"""One avatar from Python, timed like caliper_bench's BM_MapEstimate/1/0 (docs/performance.md).

The same request: the built-in female body, a trained builder kept (a loaded caliper.Model), the
six Virtual Caliper inputs of bench_core.cpp's typical_inputs(), estimator auto with exact noise,
the full avatar (every measurement's and vertex's SD, the avatar measured). Prints the median of
--repetitions runs of the mean time per call over at least --min-time seconds, as Google
Benchmark reports it.

    PYTHONPATH=build/python taskset -c 1 /usr/bin/python3 bench/python_avatar.py

With --against build/bin/caliper_bench it alternates: one C++ run of BM_MapEstimate/1/0 (a
subprocess, one repetition of --min-time), then one Python run of the same length, --rounds
times, and prints the median of the per-round ratios Python CPU / C++ CPU. On a machine whose
speed drifts (a shared virtual machine) the ratio of neighbouring runs is steadier than either
series.
"""
import argparse
import json
import statistics
import subprocess
import time

import caliper

PERSON = dict(stature_cm=165, weight_kg=62, span_cm=167, crotch_height_cm=77, hip_breadth_cm=36, arm_length_cm=55)


def mean_seconds_per_avatar(model, min_time):
    """(wall, CPU) seconds per call, as Google Benchmark's Time and CPU columns."""
    calls, start, start_cpu = 0, time.perf_counter(), time.process_time()
    while True:
        caliper.build_avatar(model=model, **PERSON)
        calls += 1
        elapsed = time.perf_counter() - start
        if elapsed >= min_time:
            return elapsed / calls, (time.process_time() - start_cpu) / calls


def cpp_cpu_seconds(bench, min_time):
    """CPU seconds per avatar of one BM_MapEstimate/1/0 run of the C++ benchmark."""
    out = subprocess.run([bench, "--benchmark_filter=MapEstimate/1/0$", f"--benchmark_min_time={min_time}",
                          "--benchmark_format=json"], check=True, capture_output=True, text=True).stdout
    run = json.loads(out)["benchmarks"][0]
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[run["time_unit"]]
    return run["cpu_time"] * scale


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--min-time", type=float, default=0.5, help="seconds per run (as --benchmark_min_time)")
    parser.add_argument("--against", metavar="CALIPER_BENCH", help="alternate with this C++ benchmark binary")
    parser.add_argument("--rounds", type=int, default=20, help="with --against: C++/Python pairs")
    args = parser.parse_args()
    model = caliper.load_model("mannequin", sex="female")
    caliper.build_avatar(model=model, **PERSON)  # warm up, as the benchmark's first iterations do
    if args.against:
        ratios, cpp, py = [], [], []
        for _ in range(args.rounds):
            cpp.append(cpp_cpu_seconds(args.against, args.min_time))
            py.append(mean_seconds_per_avatar(model, args.min_time)[1])
            ratios.append(py[-1] / cpp[-1])
        q = statistics.quantiles(ratios, n=4)
        print(f"{args.rounds} rounds: C++ CPU median {statistics.median(cpp) * 1e3:.2f} ms, Python CPU median "
              f"{statistics.median(py) * 1e3:.2f} ms; Python / C++ per round: median {statistics.median(ratios):.3f} "
              f"(quartiles {q[0]:.3f}–{q[2]:.3f})")
        return
    runs = [mean_seconds_per_avatar(model, args.min_time) for _ in range(args.repetitions)]
    wall = statistics.median(r[0] for r in runs) * 1e3
    cpu = statistics.median(r[1] for r in runs) * 1e3
    print(f"python build_avatar (auto, full avatar): median {wall:.2f} ms, CPU {cpu:.2f} ms, "
          f"over {args.repetitions} repetitions of at least {args.min_time} s")


if __name__ == "__main__":
    main()
