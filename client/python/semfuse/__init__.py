"""semfuse from Python: plug a segmenter into a running semfuse map server, publish RGB-D frames,
and query the labeled map, with numpy arrays.

    import semfuse
    client = semfuse.MapClient(domain_id=0)
    view = client.raycast(pose, semfuse.Intrinsics(640, 480, 525, 525, 319.5, 239.5))
    labels = view["labels"]                      # (480, 640) uint16

The classes are the C++ client library's (semfuse::client), bound with pybind11: every call that
waits on DDS releases the interpreter's lock. See the package README for the whole API.
"""
from __future__ import annotations

import atexit as _atexit

from ._errors import CallTimeout, ClientError, Error, ServerError
from ._semfuse import (
    ALL_LAYERS,
    COLOR,
    CONFIDENCE,
    DEPTH,
    LABELS,
    NORMALS,
    CameraPublisher,
    CameraStatus,
    ErrorRecord,
    Frame,
    Intrinsics,
    LabelArea,
    LabelInfo,
    Legend,
    MapClient,
    Mesh,
    ObjectEvent,
    ObjectEvents,
    ObjectInstance,
    Participant,
    PoseIterator,
    PoseSubscription,
    ReasonCount,
    RegionSummary,
    Segmenter,
    SegmenterStats,
    ServerStatus,
    StageTiming,
    TrackedPose,
    __version__,
    set_log_level,
)
from ._semfuse import _stop_all_threads

# Threads of segmenters and pose subscriptions call into Python: stop them before the
# interpreter goes, or a thread waiting for it would hang the exit.
_atexit.register(_stop_all_threads)

__all__ = [
    "ALL_LAYERS",
    "COLOR",
    "CONFIDENCE",
    "DEPTH",
    "LABELS",
    "NORMALS",
    "CallTimeout",
    "CameraPublisher",
    "CameraStatus",
    "ClientError",
    "Error",
    "ErrorRecord",
    "Frame",
    "Intrinsics",
    "LabelArea",
    "LabelInfo",
    "Legend",
    "MapClient",
    "Mesh",
    "ObjectEvent",
    "ObjectEvents",
    "ObjectInstance",
    "Participant",
    "PoseIterator",
    "PoseSubscription",
    "ReasonCount",
    "RegionSummary",
    "Segmenter",
    "SegmenterStats",
    "ServerError",
    "ServerStatus",
    "StageTiming",
    "TrackedPose",
    "__version__",
    "set_log_level",
]
