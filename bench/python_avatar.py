"""One avatar from Python, timed like caliper_bench's BM_MapEstimate/1/0 (docs/performance.md).

The same request: the built-in female body, a trained builder kept (a loaded caliper.Model), the
six Virtual Caliper inputs of bench_core.cpp's typical_inputs(), estimator auto with exact noise,
the full avatar (every measurement's and vertex's SD, the avatar measured). Prints the median of
REPETITIONS runs of the mean time per call over at least MIN_TIME seconds, as Google Benchmark
reports it.

    PYTHONPATH=build/python taskset -c 1 /usr/bin/python3 bench/python_avatar.py
"""
import statistics
import time

import caliper

REPETITIONS = 5
MIN_TIME = 0.5  # seconds per repetition, as --benchmark_min_time=0.5
PERSON = dict(stature_cm=165, weight_kg=62, span_cm=167, crotch_height_cm=77, hip_breadth_cm=36, arm_length_cm=55)


def mean_seconds_per_avatar(model):
    """(wall, CPU) seconds per call, as Google Benchmark's Time and CPU columns."""
    calls, start, start_cpu = 0, time.perf_counter(), time.process_time()
    while True:
        caliper.build_avatar(model=model, **PERSON)
        calls += 1
        elapsed = time.perf_counter() - start
        if elapsed >= MIN_TIME:
            return elapsed / calls, (time.process_time() - start_cpu) / calls


def main():
    model = caliper.load_model("mannequin", sex="female")
    caliper.build_avatar(model=model, **PERSON)  # warm up, as the benchmark's first iterations do
    runs = [mean_seconds_per_avatar(model) for _ in range(REPETITIONS)]
    wall = statistics.median(r[0] for r in runs) * 1e3
    cpu = statistics.median(r[1] for r in runs) * 1e3
    print(f"python build_avatar (auto, full avatar): median {wall:.2f} ms, CPU {cpu:.2f} ms, "
          f"over {REPETITIONS} repetitions of at least {MIN_TIME} s")


if __name__ == "__main__":
    main()
