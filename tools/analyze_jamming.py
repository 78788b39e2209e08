#!/usr/bin/python3
"""tools/analyze_jamming.py: the command jamsim_analysis.scripts.analyze_jamming (installed as jamsim-analyze-jamming);
--help says what it computes. Run from a checkout, this folder is on sys.path first."""
import sys

from jamsim_analysis.scripts import analyze_jamming

if __name__ == "__main__":
    sys.exit(analyze_jamming.main())
