// A small whole slider: an nx × ny post lattice under a free-standing body with margins on all
// four sides, for the direct FEM check of the lattice model (crates/slider-contact,
// tests/direct_fem.rs). No stator (its half-space enters analytically, as in the lattice model).
//
// Body box x in [0, L], y in [0, W], z in [h, h + t], L = nx pitch + 2 margin, W = ny pitch +
// 2 margin; posts (diameter d, height h) at x = margin + (i + 0.5) pitch, y = margin + (j + 0.5)
// pitch, tips at z = 0. A ball patch (disk of radius rb at (bx, by)) is imprinted on the top face.
//
// Mesh size: h_post on the post tips and root circles, h_ball on the ball patch's rim, each
// growing linearly with the distance, size = min(h_post + growth dist, h_ball + growth dist, h_body).
//
// Parameters (metres): pitch, d, h, t, nx, ny, margin, bx, by, rb, h_post, h_ball, h_body,
// growth, order. Physical groups: volume "slider"; surfaces "post_tips", "slider_top" (the whole
// top face, ball patch included), "ball" (the patch).

SetFactory("OpenCASCADE");
General.AbortOnError = 4;

DefineConstant[
  pitch = {40e-6, Name "Parameters/pitch (m)"},
  d = {20e-6, Name "Parameters/d (m)"},
  h = {2e-6, Name "Parameters/h (m)"},
  t = {0.5e-3, Name "Parameters/t (m)"},
  nx = {3, Name "Parameters/nx"},
  ny = {3, Name "Parameters/ny"},
  margin = {0.5e-3, Name "Parameters/margin (m)"},
  bx = {0.56e-3, Name "Parameters/bx (ball x, m)"},
  by = {0.56e-3, Name "Parameters/by (ball y, m)"},
  rb = {50e-6, Name "Parameters/rb (ball patch radius, m)"},
  h_post = {5e-6, Name "Parameters/h_post (m)"},
  h_ball = {20e-6, Name "Parameters/h_ball (m)"},
  h_body = {100e-6, Name "Parameters/h_body (m)"},
  growth = {0.3, Name "Parameters/growth"},
  order = {1, Choices{1 = "Tet4", 2 = "Tet10"}, Name "Parameters/order"}
];

If (pitch <= 0 || d <= 0 || h <= 0 || t <= 0 || margin < 0 || rb <= 0 || d >= pitch)
  Error("slider-block.geo: need pitch, d, h, t, rb > 0, margin >= 0 and d < pitch");
  Abort;
EndIf
If (nx < 1 || ny < 1 || nx != Round(nx) || ny != Round(ny))
  Error("slider-block.geo: nx and ny must be positive integers");
  Abort;
EndIf
If (h_post <= 0 || h_ball <= 0 || h_body < h_post || growth <= 0 || (order != 1 && order != 2))
  Error("slider-block.geo: need 0 < h_post <= h_body, h_ball > 0, growth > 0, order 1 or 2");
  Abort;
EndIf

unit = 1e-6;
Mesh.ScalingFactor = unit;
P = pitch / unit;
D = d / unit;
H = h / unit;
T = t / unit;
M = margin / unit;
L = nx * P + 2 * M;
W = ny * P + 2 * M;
BX = bx / unit;
BY = by / unit;
RB = rb / unit;
If (BX - RB <= 0 || BX + RB >= L || BY - RB <= 0 || BY + RB >= W)
  Error("slider-block.geo: the ball patch (bx, by, rb) must lie inside the top face");
  Abort;
EndIf
eps = 1e-3 * H;

Box(1) = {0, 0, H, L, W, T};
n_tips = nx * ny;
For j In {0 : ny - 1}
  For i In {0 : nx - 1}
    Cylinder(100 + j * nx + i) = {M + (i + 0.5) * P, M + (j + 0.5) * P, 0, 0, 0, H, D / 2};
  EndFor
EndFor
fused() = BooleanUnion{ Volume{1}; Delete; }{ Volume{100 : 100 + n_tips - 1}; Delete; };
Disk(900000) = {BX, BY, H + T, RB};
slider() = BooleanFragments{ Volume{fused()}; Delete; }{ Surface{900000}; Delete; };
slider() = Volume In BoundingBox{-eps, -eps, -eps, L + eps, W + eps, H + T + eps};
If (#slider() != 1)
  Error("slider-block.geo: internal error: the slider is not one volume");
  Abort;
EndIf

Macro FacesInBox
  picked() = {};
  candidates() = Surface In BoundingBox{box(0), box(1), box(2), box(3), box(4), box(5)};
  For fi In {0 : #candidates() - 1}
    For fj In {0 : #body_faces() - 1}
      If (candidates(fi) == body_faces(fj))
        picked() += candidates(fi);
      EndIf
    EndFor
  EndFor
Return

body_faces() = Abs(Boundary{ Volume{slider()}; });
box() = {-eps, -eps, -eps, L + eps, W + eps, eps};
Call FacesInBox;
post_tips() = picked();
box() = {-eps, -eps, H + T - eps, L + eps, W + eps, H + T + eps};
Call FacesInBox;
slider_top() = picked();
box() = {BX - RB - eps, BY - RB - eps, H + T - eps, BX + RB + eps, BY + RB + eps, H + T + eps};
Call FacesInBox;
ball() = picked();
If (#post_tips() != n_tips || #ball() != 1 || #slider_top() != 2)
  Error("slider-block.geo: internal error: %g tips (expected %g), %g ball faces, %g top faces",
        #post_tips(), n_tips, #ball(), #slider_top());
  Abort;
EndIf

Physical Volume("slider", 1) = slider();
Physical Surface("post_tips", 11) = post_tips();
Physical Surface("slider_top", 12) = slider_top();
Physical Surface("ball", 13) = ball();

root_edges() = Curve In BoundingBox{-eps, -eps, H - eps, L + eps, W + eps, H + eps};
ball_rim() = Curve In BoundingBox{BX - RB - eps, BY - RB - eps, H + T - eps, BX + RB + eps, BY + RB + eps, H + T + eps};
Field[1] = Distance;
Field[1].SurfacesList = {post_tips()};
Field[1].CurvesList = {root_edges()};
Field[1].NumPointsPerCurve = Ceil(Pi * D / (h_post / unit)) * 2 + 20;
Field[2] = Distance;
Field[2].CurvesList = {ball_rim()};
Field[2].NumPointsPerCurve = Ceil(2 * Pi * RB / (h_ball / unit)) * 2 + 20;
Field[3] = MathEval;
Field[3].F = Sprintf("Min(Min(%.17g + %.17g * F1, %.17g + %.17g * F2), %.17g)",
                     h_post / unit, growth, h_ball / unit, growth, h_body / unit);
Background Field = 3;

Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.LcIntegrationPrecision = 1e-4;
Mesh.Algorithm3D = 1;
Mesh.Optimize = 1;
Mesh.ElementOrder = order;
Mesh.SecondOrderLinear = 0;
Mesh.HighOrderOptimize = 0;
