// Strip of the textured silicon slider, `rows` post pitches wide in y (default one), pressed on a
// LiNbO3 stator block.
//
// Slider: body box x in [0, L], y in [0, W], z in [h, h + t] with n_posts x rows cylindrical posts
// (diameter d, height h) standing on its underside, post tips facing down at z = 0; post centres
// at x = margin + (i + 0.5) pitch, y = (r + 0.5) pitch; L = n_posts pitch + 2 margin,
// W = rows pitch. The planes y = 0 and y = W are symmetry planes of the textured surface.
// Stator (stator_depth > 0): box x in [0, L], y in [0, W], z in [-stator_depth, 0], a separate
// body (no shared nodes with the slider), with the post-tip circles imprinted on its top face so
// that both sides resolve the contact disks (the two meshes need not match node for node).
// half_y = 1 (one row only) keeps the half y <= W/2 of the strip: the plane y = W/2 through the post
// axes is a mirror plane of the one-row strip (geometry and a load uniform in y), so the half with
// a symmetry plane there has the whole strip's solution with half the unknowns; the post tips
// become half disks whose straight edge lies on y = W/2 (both bodies are cut).
// periodic_x = 1 makes the x = L faces periodic copies (node-matching, gmsh "Periodic Surface")
// of the x = 0 faces, for both bodies; the $Periodic section of the MSH file lists the node pairs.
// mirror_x = 1 (n_posts even, periodic_x = 0) meshes only the half x <= L/2 (the first n_posts/2
// posts): the strip is mirror-symmetric about x = L/2, and the reader makes the whole mesh by
// reflecting this half in that plane (gmsh_mesh::mirror), in about half of gmsh's time. The cut
// faces at x = L/2 are named "slider_mirror_x" / "stator_mirror_x"; there is no x = L face.
//
// Mesh size: h_post on the post tips and on the stator disks under them, growing linearly with the
// distance from them, size = min(h_post + growth * dist, h_body).
//
// Parameters (metres; override with gmsh -setnumber NAME VALUE; see meshes/README.md):
//   pitch, d, h, t, n_posts, rows, margin, stator_depth, h_post, h_body, growth, order, periodic_x,
//   half_y, mirror_x
//
// Physical groups: volumes "slider" (body and posts), "stator" (if stator_depth > 0); surfaces
// "post_tips", "post_walls", "slider_top", "slider_sym_y0", "slider_sym_y1", "slider_x0", "slider_x1",
// "stator_top", "stator_bottom", "stator_sym_y0", "stator_sym_y1", "stator_x0", "stator_x1",
// "stator_tip_disks"; with mirror_x = 1 "slider_mirror_x" and "stator_mirror_x" instead of the
// two x1 groups.

SetFactory("OpenCASCADE");
// Any Error() below, or a meshing error, exits gmsh with a non-zero status and no output file.
General.AbortOnError = 4;

DefineConstant[
  pitch = {40e-6, Name "Parameters/pitch (m)"},
  d = {20e-6, Name "Parameters/d (post diameter, m)"},
  h = {2e-6, Name "Parameters/h (post height, m)"},
  t = {0.5e-3, Name "Parameters/t (slider body thickness, m)"},
  n_posts = {10, Name "Parameters/n_posts"},
  rows = {1, Name "Parameters/rows (posts across the strip)"},
  margin = {0, Name "Parameters/margin (body beyond the end posts, m)"},
  stator_depth = {1e-3, Name "Parameters/stator_depth (m, 0: no stator)"},
  h_post = {2.5e-6, Name "Parameters/h_post (element size at the post tips, m)"},
  h_body = {100e-6, Name "Parameters/h_body (far element size, m)"},
  growth = {0.3, Name "Parameters/growth (size growth per unit distance)"},
  order = {1, Choices{1 = "Tet4", 2 = "Tet10"}, Name "Parameters/order"},
  periodic_x = {0, Choices{0 = "free ends", 1 = "periodic x"}, Name "Parameters/periodic_x"},
  half_y = {0, Choices{0 = "whole width", 1 = "half width (mirror plane y = W/2)"}, Name "Parameters/half_y"},
  mirror_x = {0, Choices{0 = "whole length", 1 = "half length (mirror plane x = L/2)"}, Name "Parameters/mirror_x"}
];

If (pitch <= 0 || d <= 0 || h <= 0 || t <= 0 || margin < 0 || stator_depth < 0)
  Error("slider-strip.geo: need pitch, d, h, t > 0 and margin, stator_depth >= 0");
  Abort;
EndIf
If (d >= pitch)
  Error("slider-strip.geo: post diameter d must be smaller than the pitch");
  Abort;
EndIf
If (n_posts < 1 || n_posts != Round(n_posts))
  Error("slider-strip.geo: n_posts must be a positive integer");
  Abort;
EndIf
If (rows < 1 || rows != Round(rows))
  Error("slider-strip.geo: rows must be a positive integer");
  Abort;
EndIf
If (h_post <= 0 || h_body < h_post || growth <= 0)
  Error("slider-strip.geo: need 0 < h_post <= h_body and growth > 0");
  Abort;
EndIf
If (order != 1 && order != 2)
  Error("slider-strip.geo: order must be 1 (Tet4) or 2 (Tet10)");
  Abort;
EndIf
If (periodic_x != 0 && periodic_x != 1)
  Error("slider-strip.geo: periodic_x must be 0 or 1");
  Abort;
EndIf
If (half_y != 0 && half_y != 1)
  Error("slider-strip.geo: half_y must be 0 or 1");
  Abort;
EndIf
If (mirror_x != 0 && mirror_x != 1)
  Error("slider-strip.geo: mirror_x must be 0 or 1");
  Abort;
EndIf
If (mirror_x == 1 && (periodic_x == 1 || n_posts % 2 != 0))
  Error("slider-strip.geo: mirror_x = 1 needs an even n_posts and periodic_x = 0");
  Abort;
EndIf
If (half_y == 1 && rows != 1)
  Error("slider-strip.geo: half_y = 1 needs rows = 1 (the mirror plane runs through the post axes)");
  Abort;
EndIf

// The model is built in micrometres and scaled to metres on output: OpenCASCADE works with an
// absolute tolerance of 1e-7 model units, far too coarse for micrometre features in metres.
unit = 1e-6;
Mesh.ScalingFactor = unit;
P = pitch / unit;
D = d / unit;
H = h / unit;
T = t / unit;
M = margin / unit;
S = stator_depth / unit;
L_full = n_posts * P + 2 * M;
// Length and posts per row of the meshed strip: the whole, or its half x <= L/2 (mirror_x = 1).
L = L_full / (1 + mirror_x);
n_x = n_posts / (1 + mirror_x);
W_full = rows * P;
// Width of the meshed strip: the whole width, or its half y <= W/2 (half_y = 1).
W = W_full / (1 + half_y);
// Geometric tolerance for entity identification [um] (OCC bounding boxes carry 1e-7 slack).
eps = 1e-3 * H;

// Slider: body plus posts fused into one volume.
Box(1) = {0, 0, H, L, W, T};
n_tips = n_x * rows;
For r In {0 : rows - 1}
  For i In {0 : n_x - 1}
    Cylinder(100 + r * n_x + i) = {M + (i + 0.5) * P, (r + 0.5) * P, 0, 0, 0, H, D / 2};
  EndFor
EndFor
slider() = BooleanUnion{ Volume{1}; Delete; }{ Volume{100 : 100 + n_tips - 1}; Delete; };
If (#slider() != 1)
  Error("slider-strip.geo: internal error: body and posts did not fuse into one volume");
  Abort;
EndIf
If (half_y == 1)
  // Keep y <= W: the posts' halves on this side of their axes.
  Box(3) = {-1, -1, -1, L + 2, W + 1, H + T + 2};
  slider() = BooleanIntersection{ Volume{slider()}; Delete; }{ Volume{3}; Delete; };
  If (#slider() != 1)
    Error("slider-strip.geo: internal error: the half strip is not one volume");
    Abort;
  EndIf
EndIf

// Stator block with the post-tip circles imprinted on its top face (fragmented on its own, so it
// shares no entity, and hence no node, with the slider).
stator() = {};
If (S > 0)
  Box(2) = {0, 0, -S, L, W, S};
  For r In {0 : rows - 1}
    For i In {0 : n_x - 1}
      Disk(100000 + r * n_x + i) = {M + (i + 0.5) * P, (r + 0.5) * P, 0, D / 2};
    EndFor
  EndFor
  stator() = BooleanFragments{ Volume{2}; Delete; }{ Surface{100000 : 100000 + n_tips - 1}; Delete; };
  If (half_y == 1)
    // The disks' halves beyond y = W are loose surfaces outside the block: removed.
    Delete{ Surface{ Surface In BoundingBox{-eps, W - eps, -eps, L + eps, W + D / 2 + eps, eps} }; }
  EndIf
  stator() = Volume In BoundingBox{-eps, -eps, -S - eps, L + eps, W + eps, eps};
  If (#stator() != 1)
    Error("slider-strip.geo: internal error: stator is not one volume");
    Abort;
  EndIf
EndIf

// Boundary pieces of each body, identified geometrically among that body's own faces.
Macro FacesInBox
  // in: body_faces(), box(); out: picked(), the faces in the box that belong to the body, in the
  // order gmsh lists the box's faces. List subtraction, not a nested loop over both lists: the
  // interpreted double loop took 1.0 of gmsh's 6.8 s CPU on the default 100-post half strip;
  // the picked faces, and hence the mesh bytes, are the same.
  picked() = Surface In BoundingBox{box(0), box(1), box(2), box(3), box(4), box(5)};
  others() = picked();
  others() -= body_faces();
  picked() -= others();
Return

body_faces() = Abs(Boundary{ Volume{slider()}; });
box() = {-eps, -eps, -eps, L + eps, W + eps, eps};
Call FacesInBox;
post_tips() = picked();
box() = {-eps, -eps, H + T - eps, L + eps, W + eps, H + T + eps};
Call FacesInBox;
slider_top() = picked();
box() = {-eps, -eps, -eps, L + eps, eps, H + T + eps};
Call FacesInBox;
slider_y0() = picked();
box() = {-eps, W - eps, -eps, L + eps, W + eps, H + T + eps};
Call FacesInBox;
slider_y1() = picked();
box() = {-eps, -eps, -eps, eps, W + eps, H + T + eps};
Call FacesInBox;
slider_x0() = picked();
box() = {L - eps, -eps, -eps, L + eps, W + eps, H + T + eps};
Call FacesInBox;
slider_x1() = picked();
If (#post_tips() != n_tips)
  Error("slider-strip.geo: internal error: found %g post tips, expected %g", #post_tips(), n_tips);
  Abort;
EndIf
// Post walls: the slider's faces between the tips and the underside that lie on no plane face
// (the cylinders; their triangles let a reader curve Tet4 edges onto them, gmsh_mesh::elevate).
box() = {-eps, -eps, -eps, L + eps, W + eps, H + eps};
Call FacesInBox;
post_walls() = picked();
post_walls() -= post_tips();
box() = {-eps, -eps, H - eps, L + eps, W + eps, H + eps};
Call FacesInBox;
post_walls() -= picked();
post_walls() -= slider_y0();
post_walls() -= slider_y1();
post_walls() -= slider_x0();
post_walls() -= slider_x1();
If (#post_walls() < n_tips)
  Error("slider-strip.geo: internal error: found %g post wall faces for %g posts", #post_walls(), n_tips);
  Abort;
EndIf

Physical Volume("slider", 1) = slider();
Physical Surface("post_tips", 11) = post_tips();
Physical Surface("slider_top", 12) = slider_top();
Physical Surface("slider_sym_y0", 13) = slider_y0();
Physical Surface("slider_sym_y1", 14) = slider_y1();
Physical Surface("slider_x0", 15) = slider_x0();
If (mirror_x == 1)
  Physical Surface("slider_mirror_x", 18) = slider_x1();
Else
  Physical Surface("slider_x1", 16) = slider_x1();
EndIf
Physical Surface("post_walls", 17) = post_walls();

If (S > 0)
  body_faces() = Abs(Boundary{ Volume{stator()}; });
  box() = {-eps, -eps, -eps, L + eps, W + eps, eps};
  Call FacesInBox;
  stator_top() = picked();
  box() = {-eps, -eps, -S - eps, L + eps, W + eps, -S + eps};
  Call FacesInBox;
  stator_bottom() = picked();
  box() = {-eps, -eps, -S - eps, L + eps, eps, eps};
  Call FacesInBox;
  stator_y0() = picked();
  box() = {-eps, W - eps, -S - eps, L + eps, W + eps, eps};
  Call FacesInBox;
  stator_y1() = picked();
  box() = {-eps, -eps, -S - eps, eps, W + eps, eps};
  Call FacesInBox;
  stator_x0() = picked();
  box() = {L - eps, -eps, -S - eps, L + eps, W + eps, eps};
  Call FacesInBox;
  stator_x1() = picked();
  // The imprinted tip disks: the top faces no wider than a post (their circles are the curved
  // edges of the stator; gmsh_mesh::elevate puts Tet10 midside nodes on them).
  stator_tip_disks() = {};
  For fi In {0 : #stator_top() - 1}
    bb() = BoundingBox Surface{ stator_top(fi) };
    If (bb(3) - bb(0) < D + eps)
      stator_tip_disks() += stator_top(fi);
    EndIf
  EndFor
  If (#stator_tip_disks() != n_tips)
    Error("slider-strip.geo: internal error: found %g stator tip disks, expected %g", #stator_tip_disks(), n_tips);
    Abort;
  EndIf

  Physical Volume("stator", 2) = stator();
  Physical Surface("stator_top", 21) = stator_top();
  Physical Surface("stator_bottom", 22) = stator_bottom();
  Physical Surface("stator_sym_y0", 23) = stator_y0();
  Physical Surface("stator_sym_y1", 24) = stator_y1();
  Physical Surface("stator_x0", 25) = stator_x0();
  If (mirror_x == 1)
    Physical Surface("stator_mirror_x", 28) = stator_x1();
  Else
    Physical Surface("stator_x1", 26) = stator_x1();
  EndIf
  Physical Surface("stator_tip_disks", 27) = stator_tip_disks();
EndIf

If (periodic_x == 1)
  Periodic Surface{ slider_x1() } = { slider_x0() } Translate{ L, 0, 0 };
  If (S > 0)
    Periodic Surface{ stator_x1() } = { stator_x0() } Translate{ L, 0, 0 };
  EndIf
EndIf

// Size field: distance to the post-tip disks (z = 0; shared location of the slider tips and the
// stator imprints) and to the post root circles (z = h, re-entrant edge), then linear growth.
// Only the root arcs count: the straight edges of the underside z = h (on the symmetry planes,
// the mirror cut and the free ends) are no re-entrant edges (a mirror plane continues the
// underside flat; the ends are convex), so refining along them only added nodes (14 % of the
// half strip) without a stress singularity to resolve.
edges_at_root() = Curve In BoundingBox{-eps, -eps, H - eps, L + eps, W + eps, H + eps};
root_edges() = {};
For ci In {0 : #edges_at_root() - 1}
  bb() = BoundingBox Curve{ edges_at_root(ci) };
  If (bb(4) - bb(1) > eps)
    root_edges() += edges_at_root(ci);
  EndIf
EndFor
Field[1] = Distance;
Field[1].SurfacesList = {post_tips()};
Field[1].CurvesList = {root_edges()};
Field[1].NumPointsPerCurve = Ceil(Pi * D / (h_post / unit)) * 2 + 20;
Field[2] = MathEval;
Field[2].F = Sprintf("Min(%.17g + %.17g * F1, %.17g)", h_post / unit, growth, h_body / unit);
Background Field = 2;

Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
// Relative accuracy of the size-field integral that spaces the nodes along each curve (gmsh
// default 1e-9). At 1e-9 the 1D stage took 4.0 of gmsh's 11 s CPU on the default 100-post Tet10
// strip; at 1e-4 0.15 s, with 117 850 instead of 117 553 nodes (static-contact README, Speed).
Mesh.LcIntegrationPrecision = 1e-4;
// Delaunay: deterministic on one thread (the same bytes on every run). HXT (Algorithm3D = 10) took
// 0.44 s CPU for the 3D stage of the default half strip against Delaunay's 1.5 s, but gave another
// mesh on each run (70 039 and 70 104 nodes; η at 40 N differing by 1.3e-4), so it is not used.
Mesh.Algorithm3D = 1;
Mesh.Optimize = 1;
Mesh.ElementOrder = order;
// Midside nodes are placed on the true (curved) geometry: post cylinders and tip circles. No
// elastic-analogy smoothing of the interior (HighOrderOptimize = 2): on the 100-post Tet10 strip it
// took 25 of gmsh's 34 s, raised the worst distortion only from 0.40 to 0.52 (no element below
// 0.2 either way) and changed η at 40 N by 1e-4 relative.
Mesh.SecondOrderLinear = 0;
Mesh.HighOrderOptimize = 0;
