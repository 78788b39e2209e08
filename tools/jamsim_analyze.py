#!/usr/bin/python3
"""Thin command over the jamsim_analysis package (tools/jamsim_analysis/cli.py); --help
says what it computes."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from jamsim_analysis import cli  # noqa: E402

if __name__ == "__main__":
    sys.exit(cli.analyze_main())
