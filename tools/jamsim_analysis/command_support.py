"""What every command of the package shares: running a command's body with bad input as one
line and exit status 2, pandas' display options, the command's name, checked output paths,
matplotlib on Agg, id lists in words. Imports nothing heavy at load (numpy, pandas and
matplotlib only inside the functions that need them), so --help stays quick."""
import os
import sys

from .errors import AnalysisError


def display_options():
    """pandas' options for the printed tables (set when a command runs)."""
    import pandas as pd
    pd.set_option("display.width", 160)
    pd.set_option("display.max_columns", 30)
    pd.set_option("display.max_rows", 500)
    # Six significant digits, not six decimals (which leave one digit of 2e-6).
    pd.set_option("display.float_format", lambda v: f"{v:.6g}")


def run_command(func, a, prog):
    """Run a command's body on its parsed arguments; bad input (AnalysisError) becomes one
    line on stderr and exit status 2, without a traceback."""
    display_options()
    try:
        func(a)
    except AnalysisError as e:
        print(f"{prog}: {e}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader of stdout went away (| head): nothing to say
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no second error at exit
        return 1
    except OSError as e:  # a file that cannot be written, or HDF5 on a damaged archive
        if e.filename:
            print(f"{prog}: '{e.filename}': {e.strerror or e}", file=sys.stderr)
        else:
            print(f"{prog}: {e}{' (a damaged archive?)' if _raised_in_h5py(e) else ''}", file=sys.stderr)
        return 2
    except RuntimeError as e:
        if not _raised_in_h5py(e):
            raise
        print(f"{prog}: reading an archive failed: {e} (a damaged archive?)", file=sys.stderr)
        return 2
    return 0


def _raised_in_h5py(error):
    """Whether `error` came out of h5py (HDF5 reports a damaged file as a RuntimeError)."""
    tb = error.__traceback__
    while tb is not None and tb.tb_next is not None:
        tb = tb.tb_next
    return tb is not None and "h5py" in tb.tb_frame.f_code.co_filename.replace(os.sep, "/").split("/")


def pyplot():
    """matplotlib.pyplot on the Agg backend (files, never a window), imported when a figure is drawn."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def prog_name(default):
    """The command's name as the user ran it (bin/jamsim-NAME, tools/NAME.py: sys.argv[0]);
    `default` when it runs otherwise (python3 -m pytest, an interpreter)."""
    name = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else ""
    return name if name.startswith("jamsim") or (name.endswith(".py") and name != "__main__.py") else default


def output_directory(path, what="OUTDIR", create=True):
    """Create the output directory `path` (if needed; with create=False only check that it
    is not a file); refused with a message naming it."""
    name = os.path.basename(os.path.normpath(path)) if path else ""
    if not os.path.exists(path) and name != name.strip():  # 'rep ' made a folder no one sees for what it is
        raise AnalysisError(f"{what} '{path}' is not allowed: a folder name that neither starts nor ends with white "
                            "space")
    if os.path.exists(path) and not os.path.isdir(path):
        hint = " (the output directory comes after the archives)" if what == "OUTDIR" else ""
        raise AnalysisError(f"{what} '{path}' is an existing file, not a directory{hint}")
    if not os.path.exists(path) and os.path.splitext(path)[1].lower() in (".h5", ".hdf5"):
        raise AnalysisError(f"{what} '{path}' does not exist and ends in {os.path.splitext(path)[1]}, as an archive "
                            f"does: a mistyped archive? (name the output directory otherwise)")
    if not create:
        return path
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as e:
        raise AnalysisError(f"cannot create {what} '{path}': {e.strerror}") from None
    return path


# Figure formats (matplotlib's savefig, chosen by the name's ending) and animations (PIL).
FIGURE_SUFFIXES = (".png", ".pdf", ".svg", ".eps", ".ps", ".jpg", ".jpeg", ".tif", ".tiff", ".webp")
ANIMATION_SUFFIXES = (".gif", ".webp", ".png", ".apng")


def _is_hdf5(path):
    try:
        with open(path, "rb") as f:
            return f.read(8) == b"\x89HDF\r\n\x1a\n"
    except OSError:
        return False


def output_file(path, what="FIGURE", inputs=(), suffixes=None):
    """Check, before any work, that the file `path` can be written: its directory exists, it
    is not a directory, not one of the `inputs`, not an HDF5 file (an archive is never
    overwritten), and, when `suffixes` is given, its name ends in one of them (the format
    comes from the name)."""
    if not path:
        raise AnalysisError(f"{what} '': an empty file name")
    folder = os.path.dirname(path) or "."
    if os.path.isdir(path):
        raise AnalysisError(f"{what} '{path}' is a directory, not a file name")
    if not os.path.isdir(folder):
        raise AnalysisError(f"{what} '{path}': no directory '{folder}'")
    if not os.access(folder, os.W_OK):
        raise AnalysisError(f"{what} '{path}': the directory '{folder}' is not writable")
    if suffixes and os.path.splitext(path)[1].lower() not in suffixes:
        raise AnalysisError(f"{what} '{path}': a file name ending in {', '.join(suffixes)} (the format comes from "
                            "the name)")
    if os.path.exists(path):
        for given in inputs:
            if os.path.exists(given) and os.path.samefile(path, given):
                raise AnalysisError(f"{what} '{path}' is an input ('{given}'): name a new file")
        if _is_hdf5(path):
            raise AnalysisError(f"{what} '{path}' is an HDF5 file (an archive?), which is never overwritten: "
                                "name another file")
    return path


def write_beside(path, write):
    """Call write(tmp) on a new file beside `path` (a unique name, so no file of the user's is
    overwritten), then rename it to `path`: a failure leaves no partial file under the name."""
    import tempfile
    try:
        fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path) or ".", prefix=os.path.basename(path) + ".",
                                   suffix=".tmp")
    except OSError as e:
        raise AnalysisError(f"'{path}' cannot be written: {e.strerror}") from None
    mask = os.umask(0)  # mkstemp makes the file for its owner alone: give it a new file's mode
    os.umask(mask)
    os.chmod(tmp, 0o666 & ~mask)
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, path)
    except OSError as e:
        raise AnalysisError(f"writing '{path}' failed: {e.strerror} (nothing was left under its name)") from None
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def run_script(prog, func, args):
    """Run a script's body; bad input (AnalysisError) becomes one line on stderr and exit
    status 2, without a traceback."""
    return run_command(func, args, prog)


def describe_ids(ids):
    """'0-5, 7, 9-11' for a sorted list of integers."""
    ids, parts, k = sorted(ids), [], 0
    while k < len(ids):
        j = k
        while j + 1 < len(ids) and ids[j + 1] == ids[j] + 1:
            j += 1
        parts.append(str(ids[k]) if j == k else f"{ids[k]}-{ids[j]}")
        k = j + 1
    return ", ".join(parts) if parts else "none"
