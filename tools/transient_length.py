#!/usr/bin/python3
"""tools/transient_length.py: the command jamsim_analysis.scripts.transient_length (installed as jamsim-transient-length);
--help says what it computes. Run from a checkout, this folder is on sys.path first."""
import sys

from jamsim_analysis.scripts import transient_length

if __name__ == "__main__":
    sys.exit(transient_length.main())
