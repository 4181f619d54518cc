#pragma once
// How the labeled surface is grouped into objects (grouping.hpp), as a plain struct: the server's
// --objects-* options and semfuse-eval fill it; the member initializers are the defaults.
#include <Eigen/Core>

namespace semfuse::objects {

struct ObjectParams {
  // A group whose surface is smaller than this is a fragment: it joins the object it touches most
  // where there is one, and is left out of answers unless they ask for fragments.
  double min_object_area_m2 = 0.02;
  // Two neighbouring surface voxels lie on one smooth patch when their normals differ by less.
  double smooth_angle_deg = 30.0;
  // A step between two surface voxels is concave when their normals turn towards each other along
  // it: (n_q - n_p) . (q - p) / |q - p| below minus this.
  double concavity_tolerance = 0.15;
  // A boundary between two patches is concave when more than this share of its steps are.
  double concave_boundary_share = 0.5;
  // Gravity's up in the map frame, unit; zero when unknown. Where two objects of one class meet at
  // a concave crease, one stands on the other (a box on a box: two objects) when the crease's
  // valley opens upwards, and is a part of it otherwise (a leg under a table top: the valley opens
  // downwards; two walls: sideways). Unknown, every such pair is one object.
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  // Take up from the surface labeled floor instead where there is enough of it
  // (object_tracker.hpp upFromFloor); `up` is the fallback.
  bool up_from_floor = false;
  // A valley opens upwards when the sum of the two sides' mean normals is within this of up.
  double support_valley_angle_deg = 55.0;
  // A region of one label that lies inside the box (grown by the margin) of a region of its label
  // at least this many times larger joins it: a piece cut off by what stands in front.
  double enclosed_area_ratio = 20.0;
  double enclosing_margin_m = 0.1;
  // A voxel's panoptic instance counts when its evidence reaches this many observations.
  int min_instance_evidence = 2;
};

}  // namespace semfuse::objects
