#!/usr/bin/python3
"""tools/jamsim_analyze.py: the command jamsim_analysis.cli.analyze_main (installed as jamsim-analyze);
--help says what it computes. Run from a checkout, this folder is on sys.path first."""
import sys

from jamsim_analysis import cli

if __name__ == "__main__":
    sys.exit(cli.analyze_main())
