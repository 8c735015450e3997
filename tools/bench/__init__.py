"""The parts of tools/benchmark.py, the whitted benchmark (its docstring says what is measured and how).

  plan      what is measured: the scenes, the sizes, the sampling settings, the quality target
  runners   whole processes, timed: whitted on a driver, the POV-Ray exporter, POV-Ray, the scene generator
  measures  numbers from what the runs leave: whitted's record, POV-Ray's counters, PSNR, ratios, targets
  parts     the benchmark's parts, whitted against POV-Ray: fixed samples, equal quality, the drag proxy
  report    the JSON documents and the printed summary
  plot      the plot of every driver's document
  check     the --quick smoke test
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def fail(message, status=2):
    """Ends the benchmark with one line on stderr: status 2 for bad input, 1 for a failed run."""
    print(f"benchmark.py: {message}", file=sys.stderr)
    sys.exit(status)
