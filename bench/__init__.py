"""Benchmarks of jaka_driver with targets: ``python -m bench`` or ``make bench``.

One module per metric group; each measures and returns :class:`bench.report.Row` s, and
:mod:`bench.__main__` runs them in one go, writes ``bench/results/latest.{json,md}`` and the
PNG plots. Timing targets live here, never in the unit tests.
"""
