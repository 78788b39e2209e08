#!/usr/bin/python3
"""tools/plot_campaign.py: the command jamsim_analysis.scripts.plot_campaign (installed as jamsim-plot-campaign);
--help says what it computes. Run from a checkout, this folder is on sys.path first."""
import sys

from jamsim_analysis.scripts import plot_campaign

if __name__ == "__main__":
    sys.exit(plot_campaign.main())
