"""tavis_server: the reference policy server of serving protocol v1 (docs/serving.md)."""

from .lerobot_policy import LeRobotServedPolicy
from .server import PolicyServer
from .standins import EchoPolicy, SleepPolicy, StatefulCheckPolicy

__all__ = ["LeRobotServedPolicy", "PolicyServer", "EchoPolicy", "SleepPolicy", "StatefulCheckPolicy"]
