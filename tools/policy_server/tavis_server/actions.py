"""The canonical 19-D TAVIS action (kinematics/action.h): per arm an IK target position (m, canonical
frame) and a unit quaternion (w, x, y, z), the absolute neck roll/pitch/yaw, and per gripper a
scalar in [-1, 1] (-1 open, +1 closed). The stand-in policies build their chunks from it. A learned
policy's replies are only shape-checked: the client itself ends an episode with an invalid action
as `invalid_action` (and clamps grippers), which is a result to record, not a server fault."""

import numpy as np

ACTION_DIM = 19
ARM_POSITION = (slice(0, 3), slice(7, 10))
ARM_QUATERNION = (slice(3, 7), slice(10, 14))
NECK = slice(14, 17)
GRIPPERS = slice(17, 19)

# Both hands in front of the robot, identity orientation, neck straight, grippers open.
NEUTRAL_ACTION = np.array([0.35, 0.2, 1.0, 1.0, 0.0, 0.0, 0.0,
                           0.35, -0.2, 1.0, 1.0, 0.0, 0.0, 0.0,
                           0.0, 0.0, 0.0,
                           -1.0, -1.0], dtype=np.float32)


def parse_action_row(text):
    """One action from a CSV row of 19 numbers ("0.35,0.2,1.0,..."); a bad row raises ValueError
    naming the row and the offending field."""
    fields = [field.strip() for field in text.split(",")]
    if len(fields) != ACTION_DIM:
        raise ValueError(f"action row {text!r} has {len(fields)} fields; a tavis action has {ACTION_DIM}")
    try:
        row = np.array([float(field) for field in fields], dtype=np.float64)
    except ValueError as error:
        raise ValueError(f"action row {text!r}: {error}") from None
    check_actions(row[None, None], f"action row {text!r}")
    return row.astype(np.float32)


def check_actions(actions, source):
    """Raises ValueError naming `source`, the entry and its value unless `actions` (..., 19) is a
    chunk the tavis client executes: finite, arm targets within 10 m, unit-norm-able arm
    quaternions and grippers in [-1, 1]."""
    actions = np.asarray(actions)
    if actions.shape[-1:] != (ACTION_DIM,):
        raise ValueError(f"{source}: actions of shape {actions.shape}; a tavis action has {ACTION_DIM} entries")
    bad = np.argwhere(~np.isfinite(actions))
    if bad.size:
        index = tuple(bad[0])
        raise ValueError(f"{source}: actions{list(index)} = {actions[index]} is not finite")
    for positions in ARM_POSITION:
        far = np.argwhere(np.abs(actions[..., positions]) > 10.0)
        if far.size:
            index = tuple(far[0])
            raise ValueError(f"{source}: arm target {actions[..., positions][index]} m at {list(index)} is beyond 10 m")
    for quaternion in ARM_QUATERNION:
        norms = np.linalg.norm(actions[..., quaternion].astype(np.float64), axis=-1)
        if (norms < 1e-6).any():
            raise ValueError(f"{source}: an arm quaternion has norm {norms.min()}")
    grippers = actions[..., GRIPPERS]
    if (np.abs(grippers) > 1.0).any():
        raise ValueError(f"{source}: gripper value {grippers[np.abs(grippers) > 1.0][0]} is outside [-1, 1]")
