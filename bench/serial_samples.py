#!/usr/bin/env python3
"""Where one of two OpenMP threads waits: the serial stretches and the imbalance of a run.

Record a 2-thread run with `perf record -e cpu-clock -o run.data COMMAND`, then
    bench/serial_samples.py run.data [N]
Each sample of the main thread is paired with the worker's sample nearest in time (within
0.3 ms). A pair where the worker is inside libgomp (waiting at a barrier or for work) and the
main thread is not counts as serial, in the main thread's function; the reverse pair counts
as imbalance, in the worker's function. Prints both totals as shares of the main thread's
samples after the worker started, and the N functions (default 20) with most of each.
"""
import bisect
import collections
import re
import signal
import subprocess
import sys

WINDOW = 3e-4  # s: two samples further apart than this are not paired
LINE = re.compile(r"\s*(\d+)\s+([\d.]+):\s+[0-9a-f]+\s+(.*)\((\S+)\)\s*$")


def samples(data):
    """(tid, time, function, dso) of every sample, in time order per thread."""
    script = subprocess.run(
        ["perf", "script", "-i", data, "-F", "tid,time,ip,sym,dso"],
        capture_output=True, text=True, check=True).stdout
    rows = []
    for line in script.splitlines():
        m = LINE.match(line)
        if m:
            rows.append((int(m.group(1)), float(m.group(2)), m.group(3).strip() or m.group(4),
                         m.group(4)))
    return rows


def nearest(times, rows, t):
    k = bisect.bisect_left(times, t)
    best = None
    for j in (k - 1, k):
        if 0 <= j < len(times) and abs(times[j] - t) < WINDOW:
            if best is None or abs(times[j] - t) < abs(times[best] - t):
                best = j
    return rows[best] if best is not None else None


def waiting(row):
    return "libgomp" in row[3]


def main():
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # piped into head: stop quietly
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    top = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    rows = samples(sys.argv[1])
    threads = collections.Counter(r[0] for r in rows).most_common(2)
    if len(threads) < 2:
        sys.exit("serial_samples.py: the run has samples of one thread only")
    main_tid, worker_tid = sorted(t for t, _ in threads)  # the main thread started first
    by_thread = {t: [r for r in rows if r[0] == t] for t in (main_tid, worker_tid)}
    times = {t: [r[1] for r in by_thread[t]] for t in by_thread}
    start = times[worker_tid][0]
    serial, imbalance = collections.Counter(), collections.Counter()
    counted = 0
    for r in by_thread[main_tid]:
        if r[1] < start:
            continue
        counted += 1
        w = nearest(times[worker_tid], by_thread[worker_tid], r[1])
        if w is not None and waiting(w) and not waiting(r):
            serial[r[2]] += 1
    for r in by_thread[worker_tid]:
        m = nearest(times[main_tid], by_thread[main_tid], r[1])
        if m is not None and waiting(m) and not waiting(r):
            imbalance[r[2]] += 1
    share = lambda n: 100.0 * n / max(counted, 1)
    print(f"{counted} main-thread samples after the worker started: serial "
          f"{share(sum(serial.values())):.1f} %, imbalance {share(sum(imbalance.values())):.1f} %")
    for title, counts in (("serial (the worker waits)", serial),
                          ("imbalance (the main thread waits)", imbalance)):
        print(title + ":")
        for name, n in counts.most_common(top):
            print(f"  {share(n):5.2f} %  {name[:100]}")


if __name__ == "__main__":
    main()
