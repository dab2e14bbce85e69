// Coarse whole-slider body for bending studies: a box length x width x thickness, no posts.
// The underside z = 0 is where the posts attach ("bottom"), the top z = thickness ("top").
//
// Parameters (metres; override with gmsh -setnumber NAME VALUE; see meshes/README.md):
//   length, width, thickness   box size (defaults: the 5 x 5 mm silicon slider, 0.5 mm thick)
//   h_size                     element size
//   order                      1 = Tet4, 2 = Tet10
//
// Physical groups: volume "slider"; surfaces "bottom" (z = 0), "top" (z = thickness),
// "x0", "x1", "y0", "y1" (the four side faces).

SetFactory("OpenCASCADE");
// Any Error() below, or a meshing error, exits gmsh with a non-zero status and no output file.
General.AbortOnError = 4;

DefineConstant[
  length = {5e-3, Name "Parameters/length (m)"},
  width = {5e-3, Name "Parameters/width (m)"},
  thickness = {0.5e-3, Name "Parameters/thickness (m)"},
  h_size = {0.5e-3, Name "Parameters/h_size (element size, m)"},
  order = {1, Choices{1 = "Tet4", 2 = "Tet10"}, Name "Parameters/order"}
];

If (length <= 0 || width <= 0 || thickness <= 0 || h_size <= 0)
  Error("slider-body.geo: need length, width, thickness, h_size > 0");
  Abort;
EndIf
If (order != 1 && order != 2)
  Error("slider-body.geo: order must be 1 (Tet4) or 2 (Tet10)");
  Abort;
EndIf

// Built in millimetres and scaled to metres on output (OpenCASCADE's absolute tolerance is
// 1e-7 model units).
unit = 1e-3;
Mesh.ScalingFactor = unit;
Lx = length / unit;
Ly = width / unit;
Lz = thickness / unit;
eps = 1e-6 * Lz;

Box(1) = {0, 0, 0, Lx, Ly, Lz};

Physical Volume("slider", 1) = {1};
Physical Surface("bottom", 11) = Surface In BoundingBox{-eps, -eps, -eps, Lx + eps, Ly + eps, eps};
Physical Surface("top", 12) = Surface In BoundingBox{-eps, -eps, Lz - eps, Lx + eps, Ly + eps, Lz + eps};
Physical Surface("x0", 13) = Surface In BoundingBox{-eps, -eps, -eps, eps, Ly + eps, Lz + eps};
Physical Surface("x1", 14) = Surface In BoundingBox{Lx - eps, -eps, -eps, Lx + eps, Ly + eps, Lz + eps};
Physical Surface("y0", 15) = Surface In BoundingBox{-eps, -eps, -eps, Lx + eps, eps, Lz + eps};
Physical Surface("y1", 16) = Surface In BoundingBox{-eps, Ly - eps, -eps, Lx + eps, Ly + eps, Lz + eps};

Mesh.MeshSizeMin = h_size / unit;
Mesh.MeshSizeMax = h_size / unit;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm3D = 1; // Delaunay
Mesh.Optimize = 1;
Mesh.ElementOrder = order;
Mesh.SecondOrderLinear = 0;
