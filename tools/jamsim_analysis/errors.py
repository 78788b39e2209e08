"""The one exception of the package: a message for the user, printed without a traceback."""


class AnalysisError(Exception):
    """Bad input for an analysis (wrong kind of archive, too few rates or seeds, an empty
    window): the message names what is missing."""
