"""Type stubs of semfuse._semfuse, the native part of the semfuse package (pybind11 over the C++
client library). tests/python/stubs_test.py checks that they name what the module has."""
from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from typing import Literal, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str

DEPTH: int
NORMALS: int
LABELS: int
CONFIDENCE: int
COLOR: int
ALL_LAYERS: int

LayerName = Literal["depth", "normals", "labels", "confidence", "color"]
Layers = Union[None, int, LayerName, Iterable[LayerName]]
ArrayLike = npt.ArrayLike
FloatArray = npt.NDArray[np.float32]

def set_log_level(level: str) -> None:
    """Level of the client library's log on stderr: trace, debug, info, warn, error, critical or off."""

def _stop_all_threads() -> None:
    """Stops every Segmenter and pose subscription still running (the package runs it at exit)."""

class Participant:
    """A DDS domain participant, shared by the objects given it (one per domain is made when none is given)."""

    def __init__(self, domain_id: int | None = None, dds_profile: str | None = None) -> None:
        """Joins DDS domain `domain_id` (None: Cyclone's default). `dds_profile`: a Cyclone XML file, applied
        when this process joins the domain for the first time. Raises semfuse.Error when DDS refuses."""
    @property
    def domain_id(self) -> int: ...

class Intrinsics:
    """Pinhole camera intrinsics in pixels, for an image of width x height."""

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float
    def __init__(self, width: int, height: int, fx: float, fy: float, cx: float, cy: float) -> None:
        """Raises ValueError for an empty image, a side above 8192 pixels, or focal lengths that are not > 0."""
    @staticmethod
    def from_matrix(K: ArrayLike, width: int, height: int) -> Intrinsics:
        """Intrinsics from a 3x3 camera matrix K and the image size."""
    @property
    def K(self) -> npt.NDArray[np.float64]:
        """The 3x3 camera matrix."""
    def scaled(self, factor: float) -> Intrinsics:
        """The same camera at another resolution (pixel centres stay consistent)."""
    def __eq__(self, other: object) -> bool: ...

class Frame:
    """An RGB-D frame as a segmenter callback receives it. The arrays are the frame's own."""

    @property
    def camera_id(self) -> str: ...
    @property
    def seq(self) -> int:
        """The camera's sequence number of the frame."""
    @property
    def stamp(self) -> float:
        """Time stamp, seconds."""
    @property
    def frame_id(self) -> str: ...
    @property
    def intrinsics(self) -> Intrinsics: ...
    @property
    def color(self) -> npt.NDArray[np.uint8] | None:
        """(H, W, 3) uint8 RGB (not OpenCV's BGR), or None."""
    @property
    def depth(self) -> FloatArray:
        """(H, W) float32 metres, 0 where there is no depth."""
    @property
    def pose(self) -> npt.NDArray[np.float64] | None:
        """4x4 camera-to-world, or None when the camera sends none."""

class TrackedPose:
    """The pose the server used for one frame, and how it got it."""

    @property
    def camera_id(self) -> str: ...
    @property
    def seq(self) -> int: ...
    @property
    def stamp(self) -> float: ...
    @property
    def frame_id(self) -> str: ...
    @property
    def state(self) -> Literal["given", "tracked", "refined", "lost", "unknown"]: ...
    @property
    def posed(self) -> bool:
        """True when the frame has a pose and goes to the map; False when tracking is lost."""
    @property
    def pose(self) -> npt.NDArray[np.float64]:
        """Camera-to-world, 4x4."""
    @property
    def inlier_ratio(self) -> float: ...
    @property
    def residual(self) -> float: ...
    @property
    def iterations(self) -> int: ...
    @property
    def track_ms(self) -> float: ...

class ReasonCount:
    """How many inputs were dropped or rejected for one reason."""

    @property
    def reason(self) -> str: ...
    @property
    def camera_id(self) -> str: ...
    @property
    def count(self) -> int: ...

class CameraStatus:
    """One camera as the server sees it."""

    @property
    def camera_id(self) -> str: ...
    @property
    def tracking_state(self) -> str: ...
    @property
    def last_seq(self) -> int: ...
    @property
    def frames_received(self) -> int: ...
    @property
    def frames_posed(self) -> int:
        """Frames given or tracked a pose."""
    @property
    def frames_integrated(self) -> int:
        """Of the posed frames, those fused."""
    @property
    def frames_skipped(self) -> int:
        """Of the posed frames, those integration passed over for a newer one (labels still fused)."""
    @property
    def frames_lost(self) -> int: ...
    @property
    def frame_rate_hz(self) -> float: ...
    @property
    def last_frame_age_s(self) -> float: ...
    @property
    def stale(self) -> bool: ...
    @property
    def lost_reason(self) -> str: ...
    @property
    def frames_since_lost(self) -> int: ...
    @property
    def relocalisations(self) -> int: ...

class ErrorRecord:
    """One of the last errors the server logged."""

    @property
    def stamp(self) -> float: ...
    @property
    def source(self) -> str: ...
    @property
    def message(self) -> str: ...

class StageTiming:
    """How long one stage of the server's work took: runs since the server started; median, 95th
    percentile and maximum over the last (at most 1,000) runs."""

    @property
    def stage(self) -> str: ...
    @property
    def count(self) -> int: ...
    @property
    def p50_ms(self) -> float: ...
    @property
    def p95_ms(self) -> float: ...
    @property
    def max_ms(self) -> float: ...

class ServerStatus:
    """The server's counters and state: what it received, integrated, dropped and rejected (by reason),
    per camera, and the map's size."""

    @property
    def server_id(self) -> str: ...
    @property
    def version(self) -> str: ...
    @property
    def uptime_s(self) -> float: ...
    @property
    def frames_received(self) -> int: ...
    @property
    def frames_posed(self) -> int: ...
    @property
    def frames_integrated(self) -> int: ...
    @property
    def frames_skipped(self) -> int: ...
    @property
    def frames_lost(self) -> int: ...
    @property
    def segmentations_received(self) -> int: ...
    @property
    def segmentations_integrated(self) -> int: ...
    @property
    def dropped(self) -> list[ReasonCount]: ...
    @property
    def rejected(self) -> list[ReasonCount]: ...
    @property
    def queued_frames(self) -> int: ...
    @property
    def pending_segmentations(self) -> int: ...
    @property
    def history_frames(self) -> int: ...
    @property
    def map_revision(self) -> int:
        """Raised by every change to the map."""
    @property
    def distance_field_revision(self) -> int:
        """The map revision the distance field reflects (0 without --esdf)."""
    @property
    def snapshot_bytes(self) -> int:
        """Bytes of the map's copies kept for queries that run without its lock (region, objects, mesh)."""
    @property
    def voxel_size(self) -> float: ...
    @property
    def truncation(self) -> float: ...
    @property
    def allocated_voxels(self) -> int: ...
    @property
    def allocated_blocks(self) -> int: ...
    @property
    def map_bytes(self) -> int: ...
    @property
    def rss_bytes(self) -> int: ...
    @property
    def cameras(self) -> list[CameraStatus]: ...
    @property
    def last_errors(self) -> list[ErrorRecord]: ...
    @property
    def map_file(self) -> str: ...
    @property
    def last_save_ok(self) -> bool: ...
    @property
    def last_save_age_s(self) -> float:
        """Negative: never saved."""
    @property
    def stages(self) -> list[StageTiming]:
        """Where the server's time goes: frame_decode, frame_queue, track, integrate, late_labels,
        map_update, distance_field (those that ran)."""
    def dropped_count(self, reason: str | None = None, camera_id: str | None = None) -> int:
        """Inputs dropped for `reason` (None: any) by `camera_id` (None: any)."""
    def rejected_count(self, reason: str | None = None, camera_id: str | None = None) -> int:
        """Inputs rejected for `reason` (None: any) by `camera_id` (None: any)."""

class LabelInfo:
    """A label of the legend: id, name and display colour."""

    @property
    def id(self) -> int: ...
    @property
    def name(self) -> str: ...
    @property
    def rgb(self) -> tuple[int, int, int]: ...

class Legend:
    """The server's labels: ids, names, colours, and which are background (never change a voxel's label)."""

    @property
    def name(self) -> str: ...
    @property
    def labels(self) -> list[LabelInfo]: ...
    @property
    def background_ids(self) -> list[int]: ...
    def name_of(self, label: int) -> str | None: ...
    def id_of(self, name: str) -> int | None: ...
    def color_of(self, label: int) -> tuple[int, int, int]: ...
    def is_background(self, label: int) -> bool: ...
    def colorize(self, labels: npt.NDArray[np.integer]) -> npt.NDArray[np.uint8]:
        """A (rows, cols) label image as a (rows, cols, 3) uint8 RGB image in the legend's colours."""
    def __contains__(self, label: int) -> bool: ...
    def __len__(self) -> int: ...

class LabelArea:
    """The surface of one label in a region."""

    @property
    def label(self) -> int: ...
    @property
    def surface_voxels(self) -> int: ...
    @property
    def area_m2(self) -> float: ...

class RegionSummary:
    """What the map holds in a box."""

    @property
    def histogram(self) -> list[LabelArea]: ...
    @property
    def observed_voxels(self) -> int: ...
    @property
    def occupied_voxels(self) -> int: ...
    @property
    def free_voxels(self) -> int: ...
    @property
    def occupancy(self) -> float: ...

class ObjectInstance:
    """A connected labeled surface of the map."""

    @property
    def id(self) -> int: ...
    @property
    def label(self) -> int: ...
    @property
    def bbox_min(self) -> npt.NDArray[np.float64]: ...
    @property
    def bbox_max(self) -> npt.NDArray[np.float64]: ...
    @property
    def centroid(self) -> npt.NDArray[np.float64]: ...
    @property
    def voxel_count(self) -> int: ...
    @property
    def mean_confidence(self) -> float: ...
    @property
    def area_m2(self) -> float: ...
    @property
    def box_center(self) -> npt.NDArray[np.float64]: ...
    @property
    def box_half_extents(self) -> npt.NDArray[np.float64]: ...
    @property
    def box_rotation(self) -> npt.NDArray[np.float64]:
        """(3, 3) rotation from the box's axes to the world: its columns are the axes."""
    @property
    def fragment(self) -> bool: ...
    @property
    def frames(self) -> list[tuple[str, int]]:
        """(camera_id, seq) of the frames that saw it, those that saw most of its surface first (at most 16)."""
    @property
    def frame_count(self) -> int:
        """How many frames saw it, as far as its 8^3 leaves remember (each the latest 16 that saw it)."""

class ObjectEvent:
    """One change of the map's objects."""

    @property
    def kind(self) -> str: ...
    @property
    def id(self) -> int: ...
    @property
    def label(self) -> int: ...
    @property
    def others(self) -> list[int]: ...

class ObjectEvents:
    """The events of one update of the map's objects."""

    @property
    def update(self) -> int: ...
    @property
    def stamp(self) -> float: ...
    @property
    def object_count(self) -> int: ...
    @property
    def events(self) -> list[ObjectEvent]: ...

class Mesh:
    """The map's mesh as arrays and as the PLY file the server sent."""

    @property
    def vertices(self) -> FloatArray:
        """(N, 3) float32, world frame, metres."""
    @property
    def faces(self) -> npt.NDArray[np.uint32]:
        """(M, 3) vertex indices, counter-clockwise seen from free space."""
    @property
    def normals(self) -> FloatArray | None: ...
    @property
    def colors(self) -> npt.NDArray[np.uint8] | None:
        """(N, 3) RGB, the legend's colour of each vertex's label."""
    @property
    def labels(self) -> npt.NDArray[np.uint16] | None: ...
    @property
    def scores(self) -> FloatArray | None: ...
    @property
    def ply(self) -> bytes:
        """The binary PLY file."""
    def save(self, path: str) -> None:
        """Writes the PLY file to `path`."""

class RaycastImages(TypedDict, total=False):
    """What MapClient.raycast returns: the layers asked for."""

    depth: FloatArray  # (H, W) metres along z, 0 = no surface
    normals: FloatArray  # (H, W, 3) world frame
    labels: npt.NDArray[np.uint16]  # (H, W), 0 = unlabeled
    confidence: FloatArray  # (H, W) label score
    color: npt.NDArray[np.uint8]  # (H, W, 3) RGB

class VoxelSamples(TypedDict):
    """What MapClient.labels_at returns: one entry per point."""

    observed: npt.NDArray[np.bool_]
    label: npt.NDArray[np.uint16]
    confidence: FloatArray
    tsdf: FloatArray
    weight: FloatArray

class DistanceSamples(TypedDict):
    """What MapClient.distances returns: one entry per point."""

    known: npt.NDArray[np.bool_]  # False: nobody observed the point
    beyond: npt.NDArray[np.bool_]  # no surface within the field's maximum distance
    distance: FloatArray  # metres, negative inside obstacles
    gradient: FloatArray  # (N, 3) unit, away from the nearest surface in free space

class OccupancySlice(TypedDict):
    """What MapClient.occupancy_slice returns (nav_msgs/OccupancyGrid's layout)."""

    cells: npt.NDArray[np.int8]  # (H, W): 0 free, 99 inflated, 100 occupied, -1 unknown
    resolution: float
    origin: npt.NDArray[np.float64]  # (2,) x, y of cell (0, 0)'s minimum corner
    z: float
    frame_id: str

class SemanticSamples(TypedDict):
    """What MapClient.semantic_distances returns: one entry per point."""

    found: npt.NDArray[np.bool_]
    label: npt.NDArray[np.uint16]
    distance: FloatArray
    direction: FloatArray  # (N, 3) unit, towards surface_point
    surface_point: npt.NDArray[np.float64]  # (N, 3)

class SemanticSlice(TypedDict):
    """What MapClient.semantic_slice returns."""

    distance: FloatArray  # (H, W) metres, +inf where no surface of the labels exists
    min: npt.NDArray[np.float64]  # (2,)
    resolution: float
    z: float

class SegmentChecks(TypedDict):
    """What MapClient.check_segments returns: one entry per segment."""

    status: npt.NDArray[np.uint8]  # 0 free, 1 collision, 2 unknown
    fraction: FloatArray
    blocked_at: npt.NDArray[np.float64]  # (N, 3)
    min_clearance: FloatArray

class PoseIterator(Iterator[TrackedPose]):
    """The server's poses as they arrive (MapClient.poses())."""

    def __iter__(self) -> PoseIterator: ...
    def __next__(self) -> TrackedPose: ...

class PoseSubscription:
    """Delivers the server's poses to a callback (MapClient.subscribe_poses); closes on leaving a `with`."""

    def close(self) -> None:
        """Stops the deliveries; the callback is not called after close() returns."""
    @property
    def closed(self) -> bool: ...
    @property
    def delivered(self) -> int: ...
    @property
    def callback_errors(self) -> int: ...
    @property
    def last_error(self) -> str: ...
    def __enter__(self) -> PoseSubscription: ...
    def __exit__(self, *args: object) -> None: ...

class MapClient:
    """Queries the semfuse map server. Every query blocks until the reply comes or its timeout passes,
    with the interpreter's lock released, and raises on failure: CallTimeout (a TimeoutError) when no
    server answers in time, ServerError (with the server's message and `reason`) when it refuses,
    ClientError when its reply cannot be read. Poses are 4x4 camera-to-world matrices, metres."""

    def __init__(self, participant: Participant | None = None, domain_id: int | None = None,
                 timeout: float = 10.0) -> None:
        """Connects to the server on DDS domain `domain_id` (or through `participant`); `timeout` is every
        call's default, seconds."""
    @property
    def timeout(self) -> float: ...
    @property
    def domain_id(self) -> int: ...
    def raycast(self, pose: ArrayLike, intrinsics: Intrinsics, layers: Layers = None, max_range: float = 0.0,
                timeout: float | None = None) -> RaycastImages:
        """Renders the map from a camera: the layers asked for (None: all; bits DEPTH | LABELS; or names)."""
    def labels_at(self, points: ArrayLike, timeout: float | None = None) -> VoxelSamples:
        """The voxels at (N, 3) world points."""
    def region(self, box_min: ArrayLike, box_max: ArrayLike, timeout: float | None = None) -> RegionSummary:
        """Label surface areas and occupancy inside the box."""
    def objects(self, label: int = 0, min_voxels: int = 0, near: ArrayLike | None = None, radius: float = 0.0,
                include_fragments: bool = False, max_age: float = 0.0,
                timeout: float | None = None) -> list[ObjectInstance]:
        """Connected labeled surfaces of `label` (0: every label) with at least `min_voxels` voxels; with
        `near`, only those within `radius` metres of that point; `include_fragments` adds the pieces too
        small to be objects; with `max_age` (seconds) the objects the server grouped in the background
        from a map at most that much older will do."""
    def mesh(self, box_min: ArrayLike | None = None, box_max: ArrayLike | None = None,
             timeout: float | None = None) -> Mesh:
        """The labeled mesh of the map (or of the box); the timeout applies to each chunk."""
    def distances(self, points: ArrayLike, timeout: float | None = None) -> DistanceSamples:
        """Signed distance and unit gradient at (N, 3) world points (servers started with --esdf)."""
    def occupancy_slice(self, z_min: float = 0.1, z_max: float = 1.0, bounds_min: ArrayLike | None = None,
                        bounds_max: ArrayLike | None = None, inflation_radius: float = 0.0,
                        timeout: float | None = None) -> OccupancySlice:
        """A 2D occupancy grid of the height band, over the observed extent or the x, y box."""
    def semantic_distances(self, labels: Iterable[int], points: ArrayLike,
                           timeout: float | None = None) -> SemanticSamples:
        """Distance and direction from (N, 3) points to the nearest surface of any of `labels`."""
    def semantic_slice(self, labels: Iterable[int], z: float, bounds_min: ArrayLike, bounds_max: ArrayLike,
                       resolution: float = 0.05, timeout: float | None = None) -> SemanticSlice:
        """That distance over the horizontal plane at height z, in the x, y box."""
    def check_segments(self, starts: ArrayLike, ends: ArrayLike, radius: float = 0.0,
                       timeout: float | None = None) -> SegmentChecks:
        """Whether a sphere of `radius` moved along each segment stays clear."""
    def status(self, timeout: float | None = None) -> ServerStatus:
        """Asks the server for its status now."""
    def latest_status(self) -> ServerStatus | None:
        """The newest status the server published, or None before the first one."""
    def wait_for_status(self, timeout: float | None = None) -> ServerStatus:
        """The newest published status, waiting for the first; raises CallTimeout."""
    def legend(self, timeout: float | None = None) -> Legend:
        """The server's label legend, waiting for it; raises CallTimeout."""
    def latest_legend(self) -> Legend | None: ...
    def save(self, path: str = "", timeout: float | None = None) -> ServerStatus:
        """Saves the map to `path` on the server's host ('': the server's own map file)."""
    def load(self, path: str, timeout: float | None = None) -> ServerStatus:
        """Replaces the map with the file `path` on the server's host."""
    def reset(self, timeout: float | None = None) -> ServerStatus:
        """Empties the map."""
    def take_poses(self, timeout: float = 0.0) -> list[TrackedPose]:
        """The poses published since the last call, waiting up to `timeout` seconds for the first."""
    def poses(self, idle_timeout: float | None = None) -> PoseIterator:
        """An iterator over the server's poses as they come; it ends after `idle_timeout` seconds without one."""
    def subscribe_poses(self, callback: Callable[[TrackedPose], object]) -> PoseSubscription:
        """Calls `callback(pose)` on a thread of its own for every pose, until the subscription is closed."""
    @property
    def rejected_poses(self) -> int: ...
    def take_object_events(self, timeout: float = 0.0) -> list[ObjectEvents]:
        """The updates of the map's objects since the last call, waiting up to `timeout` seconds for the first."""
    @property
    def rejected_object_events(self) -> int: ...

class SegmenterStats:
    """What a Segmenter did so far."""

    @property
    def received(self) -> int: ...
    @property
    def not_selected(self) -> int: ...
    @property
    def skipped(self) -> int: ...
    @property
    def segmented(self) -> int: ...
    @property
    def published(self) -> int: ...
    @property
    def failed(self) -> int:
        """Callback errors, invalid results, undecodable frames, write errors."""
    @property
    def callback_errors(self) -> int: ...
    @property
    def invalid_results(self) -> int: ...
    @property
    def last_error(self) -> str: ...
    @property
    def mean_segment_ms(self) -> float: ...
    @property
    def last_segment_ms(self) -> float: ...

SegmentResult = Union[
    npt.NDArray[np.integer],
    tuple[npt.NDArray[np.integer], Union[npt.NDArray[np.floating], None]],
    tuple[npt.NDArray[np.integer], Union[npt.NDArray[np.floating], None], Union[npt.NDArray[np.integer], None]],
]

class Segmenter:
    """Runs a Python function on the frames cameras publish and publishes its labels to the server.
    The callback returns (H, W) integer labels within uint16 (at most the frame's size, 0 = unlabeled),
    or (labels, confidence) with float confidence in [0, 1] (or None), or (labels, confidence, instances)
    with a panoptic segmenter's integer instance ids of the labels' size (0 = no instance). One that
    raises or returns something else costs that frame only: it is logged and counted."""

    def __init__(self, callback: Callable[[Frame], SegmentResult], segmenter_id: str = "python-segmenter",
                 camera_id: str = "", every: int = 1, delay: float = 0.0, participant: Participant | None = None,
                 domain_id: int | None = None) -> None: ...
    def start(self) -> None: ...
    def stop(self) -> None:
        """Finishes and publishes the frame in hand, then stops."""
    def run(self, duration: float | None = None, idle_exit: float | None = None) -> SegmenterStats:
        """Blocks while the segmenter works: `duration` seconds, or until `idle_exit` seconds pass without a
        frame once frames came, or Ctrl-C."""
    def stats(self) -> SegmenterStats: ...
    @property
    def running(self) -> bool: ...
    def wait_for_camera(self, timeout: float) -> bool: ...
    def wait_for_acknowledgements(self, timeout: float) -> bool: ...
    def __enter__(self) -> Segmenter: ...
    def __exit__(self, *args: object) -> None: ...

class CameraPublisher:
    """Publishes RGB-D frames for the server to fuse (and segmenters to label)."""

    def __init__(self, camera_id: str = "python", depth_encoding: Literal["raw", "float", "png", "rvl"] = "raw",
                 color_encoding: Literal["none", "raw", "jpeg", "png"] = "jpeg", jpeg_quality: int = 90,
                 participant: Participant | None = None, domain_id: int | None = None) -> None: ...
    def publish(self, depth: npt.NDArray[np.floating] | npt.NDArray[np.uint16], intrinsics: Intrinsics,
                color: npt.NDArray[np.uint8] | None = None, pose: ArrayLike | None = None, seq: int | None = None,
                stamp: float | None = None, frame_id: str = "") -> int:
        """Encodes and writes one frame; returns its sequence number. Depth in metres (float) or millimetres
        (uint16), colour RGB."""
    def wait_for_server(self, timeout: float) -> bool: ...
    def wait_for_reader(self, timeout: float) -> bool: ...
    def wait_for_acknowledgements(self, timeout: float) -> bool: ...
    @property
    def matched_readers(self) -> int: ...
    @property
    def last_payload_bytes(self) -> int: ...
    @property
    def camera_id(self) -> str: ...
    @property
    def next_seq(self) -> int: ...
