"""Picture plumbing shared by every check's pictures (matplotlib only below here)."""

__all__ = ["PLOT_FORMATS"]

#: Formats a picture can be written in (``--plot-format``); here so that the command line
#: checks the option without importing the plotting module.
PLOT_FORMATS = ("png", "svg")
