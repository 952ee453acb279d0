"""Output files of the ``mbsym`` commands: checked before any work, written atomically, all or none.

:class:`Outputs` collects the files a command will write (``--out``, ``--plot``):

- before running, each destination is checked: its directory exists and is writable, it is not
  a directory, it is not one of the command's *input* files (``--compare``, the deck's files)
  nor another output (same file by resolved path or inode); an image name without a suffix gets
  ``.png`` (the name printed is the name written);
- each output is written to a temporary file in its destination directory;
- :meth:`Outputs.commit` renames all temporaries onto their destinations (``os.replace``,
  atomic per file) only after every output was written, so a failure (an error, Ctrl-C) leaves
  no partial or missing file behind and existing files untouched.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Iterable

from ..exceptions import OutputFileError

__all__ = ["Outputs", "IMAGE_SUFFIXES"]


def _image_suffixes() -> set[str]:
    from matplotlib.figure import Figure

    return set(Figure().canvas.get_supported_filetypes())


#: Image formats matplotlib writes (computed on first use).
IMAGE_SUFFIXES: set[str] = set()


class Outputs:
    """The output files of one command (see the module docstring).

    Parameters
    ----------
    inputs : iterable of (flag, path)
        Files the command reads (never overwritten), e.g. ``[("--compare", "ref.csv")]``.
    """

    def __init__(self, inputs: Iterable[tuple[str, str | os.PathLike]] = ()) -> None:
        self._inputs: list[tuple[str, Path]] = [(flag, Path(p)) for flag, p in inputs if p]
        self._final: dict[str, Path] = {}
        self._temp: dict[str, Path] = {}

    def add_inputs(self, inputs: Iterable[tuple[str, str | os.PathLike]]) -> None:
        """More input files (e.g. the deck's files once it is read); checks the outputs against them."""
        new = [(flag, Path(p)) for flag, p in inputs if p]
        self._inputs += new
        for flag, path in self._final.items():
            self._check_not_input(flag, path, new)

    def add(self, flag: str, path: str | os.PathLike, *, image: bool = False) -> Path:
        """Check one destination and return the path that will be written.

        Raises
        ------
        OutputFileError
            A directory, a missing or read-only directory, an input file, another output, or
            (``image=True``) a suffix matplotlib cannot write.
        """
        raw = str(path)
        if not raw.strip():
            raise OutputFileError(f"{flag} needs a file name; got an empty string")
        p = Path(raw).expanduser()
        if p.is_dir():
            raise OutputFileError(f"{flag} {raw}: is a directory; give a file name, e.g. "
                                  f"{p / ('plot.png' if image else 'out.csv')}")
        if image:
            p = _image_path(flag, p)
        parent = p.resolve().parent
        if not parent.is_dir():
            raise OutputFileError(f"{flag} {raw}: the directory {parent} does not exist; create it first")
        if not os.access(parent, os.W_OK | os.X_OK):
            raise OutputFileError(f"{flag} {raw}: the directory {parent} is not writable; choose another place")
        if p.exists() and not p.is_file():
            raise OutputFileError(f"{flag} {raw}: exists and is not a regular file; choose another name")
        if p.exists() and not os.access(p, os.W_OK):
            raise OutputFileError(f"{flag} {raw}: the file exists and is read-only; choose another name")
        self._check_not_input(flag, p, self._inputs)
        for other, q in self._final.items():
            if _same(p, q):
                raise OutputFileError(f"{flag} {raw} is also the {other} file; give the outputs different names")
        self._final[flag] = p
        return p

    def _check_not_input(self, flag: str, p: Path, inputs) -> None:
        for what, q in inputs:
            if _same(p, q):
                raise OutputFileError(f"{flag} {p} is the {what} file, which this command reads: refusing to "
                                      "overwrite it; choose another output name")

    def path(self, flag: str) -> Path:
        """The final path of an output."""
        return self._final[flag]

    def temporary(self, flag: str) -> Path:
        """A new temporary file next to the destination of ``flag`` (same suffix), to write into."""
        final = self._final[flag]
        fd, name = tempfile.mkstemp(dir=final.resolve().parent, prefix=f".{final.name}.", suffix=final.suffix)
        os.close(fd)
        self._temp[flag] = Path(name)
        return self._temp[flag]

    def commit(self) -> list[Path]:
        """Move every written temporary onto its destination; return the destinations."""
        mode = 0o666 & ~_umask()
        done = []
        for flag, tmp in self._temp.items():
            os.chmod(tmp, mode)
            os.replace(tmp, self._final[flag])
            done.append(self._final[flag])
        self._temp.clear()
        return done

    def discard(self) -> None:
        """Remove the temporaries (nothing is written)."""
        for tmp in self._temp.values():
            try:
                tmp.unlink()
            except FileNotFoundError:
                pass
        self._temp.clear()

    def __enter__(self) -> "Outputs":
        return self

    def __exit__(self, *exc) -> None:
        self.discard()


def _image_path(flag: str, p: Path) -> Path:
    if not IMAGE_SUFFIXES:
        IMAGE_SUFFIXES.update(_image_suffixes())
    suffix = p.suffix.lstrip(".").lower()
    if not suffix:
        return p.with_name(p.name + ".png")
    if suffix not in IMAGE_SUFFIXES:
        raise OutputFileError(f"{flag} {p}: unsupported image type {suffix!r}; use one of "
                              f"{', '.join(sorted(IMAGE_SUFFIXES))}")
    return p


def _same(a: Path, b: Path) -> bool:
    """The same file: equal resolved paths, or (both existing) the same inode (hard links)."""
    if a.resolve() == b.resolve():
        return True
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def _umask() -> int:
    old = os.umask(0)
    os.umask(old)
    return old
