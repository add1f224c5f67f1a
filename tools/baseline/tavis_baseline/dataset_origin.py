"""What a `tavis demos` dataset was recorded of: the tavis task and robot a checkpoint trained on it
declares it was trained for (config.json's ``task`` and ``robot``; serve.py sends them in the
observation contract, and `tavis eval` refuses a cell of another task or robot, which such a
checkpoint would only score about 0 on: docs/baselines.md).

The robot is meta/info.json's ``robot_type``; the task is the tavis name (``conditional-pick``), which
only the recording's report, tavis_demos.json, holds (meta/tasks.parquet has the scenario's class
name). A dataset of several tasks declares no task, since no one cell is its policy's; a dataset not
written by `tavis demos` (no tavis_demos.json) declares neither, its names not being tavis names."""

import json

REPORT = "tavis_demos.json"


def recorded_task_and_robot(root, info):
    """(task, robot) of the dataset in `root` whose meta/info.json holds `info`, each None when not
    known. ValueError naming the file when tavis_demos.json is there but is not a report."""
    report_path = root / REPORT
    if not report_path.is_file():
        return None, None
    try:
        report = json.loads(report_path.read_text())
        tasks = {entry["task"] for entry in report["tasks"]}
    except (UnicodeDecodeError, json.JSONDecodeError, KeyError, TypeError) as error:
        raise ValueError(f"{report_path} is not the report `tavis demos` writes ({error!r}): delete it to train "
                         f"without declaring the dataset's task and robot") from None
    robot = info.get("robot_type")
    task = next(iter(tasks)) if len(tasks) == 1 else None
    return (task if isinstance(task, str) else None), (robot if isinstance(robot, str) else None)
