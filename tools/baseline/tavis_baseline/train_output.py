"""The trainer's --out folder: what it may replace, and the training log, which joins the folder
only together with the first checkpoint it belongs to.

Until the new run's first save, its log is train_log.jsonl.tmp and every file of the checkpoint
already there (an --overwrite) stays as it was: a run interrupted before its first save loses
nothing of the old checkpoint, its log included. The first save renames the log with the
checkpoint's files; later lines go on into the same file."""

import json
import os
from pathlib import Path

from .checkpoint import FILES, TEMPORARY_SUFFIX, create_fresh, temporary_path

LOG = "train_log.jsonl"
TRAINER_FILES = FILES + (LOG,)


def _leftover(name):
    """A .tmp file of this trainer's, left by a run or a save that was interrupted."""
    return name.endswith(TEMPORARY_SUFFIX) and name[:-len(TEMPORARY_SUFFIX)] in TRAINER_FILES


def prepare(folder, overwrite):
    """Refuses an --out that would lose something, before the (long) dataset load: a file; a folder
    holding anything without --overwrite; with --overwrite, a folder holding anything this trainer
    does not write (it replaces a checkpoint, nothing else). The trainer's own .tmp leftovers are
    no checkpoint: they do not count, and are replaced."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise ValueError(f"--out {folder} is a file, not a folder")
    if not folder.is_dir():
        return
    entries = sorted(entry.name for entry in folder.iterdir() if not _leftover(entry.name))
    if entries and not overwrite:
        raise ValueError(f"--out {folder} is not empty; give --overwrite to replace the checkpoint there")
    foreign = [name for name in entries if name not in TRAINER_FILES or not (folder / name).is_file()
               or (folder / name).is_symlink()]
    if foreign:
        raise ValueError(f"--out {folder}: --overwrite replaces a tavis_baseline checkpoint ({', '.join(TRAINER_FILES)}), "
                         f"but the folder also holds {', '.join(foreign)}, which this trainer did not write; "
                         f"move it or choose another --out")


class TrainLog:
    """train_log.jsonl of a run: one JSON line per logged step."""

    def __init__(self, folder):
        self.final = Path(folder) / LOG
        self.temporary = temporary_path(self.final)
        self._file = create_fresh(self.temporary)
        self._saved = False

    def write(self, record):
        self._file.write(json.dumps(record) + "\n")
        self._file.flush()

    def staged(self):
        """What checkpoint.save must rename with the checkpoint: the log, until its first save."""
        return [] if self._saved else [(self.temporary, self.final)]

    def saved(self):
        self._saved = True

    def close(self):
        """Closes the log; one that never reached a checkpoint (the run failed first) is removed."""
        self._file.close()
        if not self._saved:
            try:
                os.unlink(self.temporary)
            except FileNotFoundError:
                pass
