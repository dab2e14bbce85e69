// Rigid flat circular punch (radius a) on an elastic half-space z <= 0, truncated at radius R.
//
// The domain is the lower hemisphere r <= R, z <= 0 (or its half y >= 0 / quarter x >= 0, y >= 0
// when sym = 1 / 2). The punch footprint, the disk r < a on z = 0, is imprinted on the top face so
// that it is a surface of its own. The mesh is graded from the punch edge (the circle r = a, z = 0,
// where the contact stress has its inverse-square-root singularity):
//     size(dist) = min(h_edge_over_a * a + growth * dist, h_max_over_a * a)
// with dist the distance to the punch edge.
//
// Parameters (override with gmsh -setnumber NAME VALUE; see meshes/README.md):
//   a              punch radius [m]
//   R_over_a       truncation radius / a (accuracy of the compliance ~ a/R; >= 100 for 0.5 %)
//   h_edge_over_a  element size at the punch edge / a
//   growth         size growth per unit distance from the edge [-] (size grows ~linearly)
//   h_max_over_a   cap on the element size / a (0: no cap beyond R/4)
//   sym            0 full, 1 half (y >= 0), 2 quarter (x >= 0, y >= 0)
//   order          1 = Tet4, 2 = Tet10 (midside nodes on the curved boundaries)
//
// Physical groups (the contract with the FEM): volume "body"; surfaces "punch" (r < a, z = 0),
// "free_surface" (r > a, z = 0), "far_field" (the hemispherical truncation surface), "sym_y0"
// (y = 0 plane, sym >= 1), "sym_x0" (x = 0 plane, sym = 2).

SetFactory("OpenCASCADE");
// Any Error() below, or a meshing error, exits gmsh with a non-zero status and no output file.
General.AbortOnError = 4;

DefineConstant[
  a = {10e-6, Name "Parameters/a (punch radius, m)"},
  R_over_a = {20, Name "Parameters/R_over_a"},
  h_edge_over_a = {0.1, Name "Parameters/h_edge_over_a"},
  growth = {0.35, Name "Parameters/growth"},
  h_max_over_a = {0, Name "Parameters/h_max_over_a (0: R/4)"},
  sym = {0, Choices{0 = "full", 1 = "half y>=0", 2 = "quarter x,y>=0"}, Name "Parameters/sym"},
  order = {1, Choices{1 = "Tet4", 2 = "Tet10"}, Name "Parameters/order"}
];

If (a <= 0 || R_over_a <= 1 || h_edge_over_a <= 0 || growth < 0 || h_max_over_a < 0)
  Error("punch.geo: need a > 0, R_over_a > 1, h_edge_over_a > 0, growth >= 0, h_max_over_a >= 0");
  Abort;
EndIf
If (sym != 0 && sym != 1 && sym != 2)
  Error("punch.geo: sym must be 0 (full), 1 (half y>=0) or 2 (quarter x,y>=0)");
  Abort;
EndIf
If (order != 1 && order != 2)
  Error("punch.geo: order must be 1 (Tet4) or 2 (Tet10)");
  Abort;
EndIf

// The model is built in units of a (a -> 1) and scaled to metres on output: OpenCASCADE works
// with an absolute tolerance of 1e-7 model units, far too coarse for micrometre geometry in metres.
Mesh.ScalingFactor = a;
R = R_over_a;
// Azimuthal extent of the model: full circle, half (0 <= phi <= pi: y >= 0), quarter (x, y >= 0).
sweep = (sym == 0) ? 2 * Pi : ((sym == 1) ? Pi : Pi / 2);

// Lower hemisphere (polar angle from -pi/2 to 0) swept over the azimuth.
Sphere(1) = {0, 0, 0, R, -Pi / 2, 0, sweep};

// Punch footprint: the disk r < a on z = 0, cut to the same azimuthal sector.
Disk(100) = {0, 0, 0, 1};
If (sym == 1)
  Rectangle(101) = {-2, 0, 0, 4, 2};
  footprint() = BooleanIntersection{ Surface{100}; Delete; }{ Surface{101}; Delete; };
ElseIf (sym == 2)
  Rectangle(101) = {0, 0, 0, 2, 2};
  footprint() = BooleanIntersection{ Surface{100}; Delete; }{ Surface{101}; Delete; };
Else
  footprint() = {100};
EndIf

// Imprint the footprint on the top face of the volume.
BooleanFragments{ Volume{1}; Delete; }{ Surface{footprint()}; Delete; }

// Identify the boundary pieces geometrically (robust to OCC's renumbering).
// Geometric tolerance for entity identification [units of a] (OCC boxes carry 1e-7 slack).
eps = 1e-4;
top() = Surface In BoundingBox{-R - eps, -R - eps, -eps, R + eps, R + eps, eps};
punch() = Surface In BoundingBox{-1 - eps, -1 - eps, -eps, 1 + eps, 1 + eps, eps};
free() = {};
For k In {0 : #top() - 1}
  is_punch = 0;
  For j In {0 : #punch() - 1}
    If (top(k) == punch(j))
      is_punch = 1;
    EndIf
  EndFor
  If (!is_punch)
    free() += top(k);
  EndIf
EndFor
sym_y0() = {};
sym_x0() = {};
If (sym >= 1)
  sym_y0() = Surface In BoundingBox{-R - eps, -eps, -R - eps, R + eps, eps, eps};
EndIf
If (sym == 2)
  sym_x0() = Surface In BoundingBox{-eps, -R - eps, -R - eps, eps, R + eps, eps};
EndIf
all() = Abs(Boundary{ Volume{:}; });
far() = {};
For k In {0 : #all() - 1}
  known = 0;
  For j In {0 : #top() - 1}
    If (all(k) == top(j))
      known = 1;
    EndIf
  EndFor
  For j In {0 : #sym_y0() - 1}
    If (all(k) == sym_y0(j))
      known = 1;
    EndIf
  EndFor
  For j In {0 : #sym_x0() - 1}
    If (all(k) == sym_x0(j))
      known = 1;
    EndIf
  EndFor
  If (!known)
    far() += all(k);
  EndIf
EndFor

Physical Volume("body", 1) = Volume{:};
Physical Surface("punch", 11) = punch();
Physical Surface("free_surface", 12) = free();
Physical Surface("far_field", 13) = far();
If (sym >= 1)
  Physical Surface("sym_y0", 14) = sym_y0();
EndIf
If (sym == 2)
  Physical Surface("sym_x0", 15) = sym_x0();
EndIf

// Punch edge: the boundary curves of the footprint that lie on the circle r = a (the straight
// cuts along the symmetry planes are excluded: they are not singular).
footprint_curves() = Abs(Boundary{ Surface{punch()}; });
edge() = {};
For k In {0 : #footprint_curves() - 1}
  bb() = BoundingBox Curve{ footprint_curves(k) };
  // A straight cut along x = 0 or y = 0 has a zero-width bounding box in x or y.
  If (bb(3) - bb(0) > eps && bb(4) - bb(1) > eps)
    edge() += footprint_curves(k);
  EndIf
EndFor
If (#edge() == 0)
  Error("punch.geo: internal error: punch edge curve not found");
  Abort;
EndIf

h_edge = h_edge_over_a;
h_max = (h_max_over_a > 0) ? h_max_over_a : R / 4;

Field[1] = Distance;
Field[1].CurvesList = {edge()};
// Sample the edge finely enough that the distance is accurate at the scale of h_edge.
Field[1].NumPointsPerCurve = Ceil(2 * Pi / h_edge) * 4 + 20;

Field[2] = MathEval;
Field[2].F = Sprintf("Min(%.17g + %.17g * F1, %.17g)", h_edge, growth, h_max);
Background Field = 2;

Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm3D = 1; // Delaunay
Mesh.Optimize = 1;
Mesh.ElementOrder = order;
// Midside nodes are placed on the true (curved) geometry: hemisphere and punch edge circle.
Mesh.SecondOrderLinear = 0;
Mesh.HighOrderOptimize = (order == 2) ? 2 : 0;
