#!/usr/bin/python3
"""tools/plot_replica.py: the command jamsim_analysis.scripts.plot_replica (installed as jamsim-plot-replica);
--help says what it computes. Run from a checkout, this folder is on sys.path first."""
import sys

from jamsim_analysis.scripts import plot_replica

if __name__ == "__main__":
    sys.exit(plot_replica.main())
