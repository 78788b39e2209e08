"""The analysis scripts of jamsim as modules of the package, each with main(argv=None):
plot_campaign, plot_replica, analyze_jamming, transient_length. They run as the installed
commands jamsim-plot-campaign, ... (tools/pyproject.toml), as `python3 -m
jamsim_analysis.scripts.NAME`, or as tools/NAME.py in a checkout."""
