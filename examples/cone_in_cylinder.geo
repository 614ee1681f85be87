// Cone-in-cylinder shot (axisymmetric, x = r, y = z, millimetres: the deck reads it with scale = "1 mm").
// The same geometry and node counts as shockfriction.coupled.cone_shot.cone_deck(cell_um=...):
// an AA5083 truncated cone (base radius Rb at z = 0, length L, half-angle alpha) in the conical bore of
// an AISI321 confinement (outer radius Ro) extended by a barrel below z = 0, where an AISI321 flyer
// (thickness H) strikes the cone base.  Transfinite (mapped) quadrilaterals, recombined.
// The confinement has its own points and curves on the bore: the cone/confinement interface is a
// slide line between non-matching sides (the bore 4/3 coarser than the cone side).
// Parameter: cell_um (cell size along the interface, um); mesh it with another value through the deck:
//   mesh = { file = "cone_in_cylinder.geo", group = "cone", scale = "1 mm", parameters = { cell_um = 400 } }
Geometry.AutoCoherence = 0;
If (!Exists(cell_um)) cell_um = 100; EndIf
L = 30; Rb = 10; Ro = 25; H = 4; alpha = 10;

Rt = Rb - L * Tan(alpha * Pi / 180);
h = cell_um * 1e-3;
slant = Hypot(L, Rb - Rt);
n_iface = Max(4, Round(slant / h));          // cone-side segments (slave)
n_guide = Max(3, Round(0.75 * n_iface));     // bore segments (guide), coarser
g = slant / n_guide;
m_barrel = Max(2, Ceil((H + 1) / g));        // barrel segments, the bore's spacing
B = m_barrel * g;
n_cone_r = Max(2, Round(Rb / (1.5 * h)));
n_conf_r = Max(3, Round((Ro - Rb) / (4 * h)));
n_flyer_z = Max(2, Round(H / (2 * h)));

// radial grading of the confinement: first cell ~ 2 h, ratio <= 1.03 (bisection, as cone_shot._grading)
W = Ro - Rb; first = 2 * h; cap = 1.03; ratio = 1;
If (n_conf_r >= 10 && W / n_conf_r > first)
  If (W * (cap - 1) / (cap^n_conf_r - 1) >= first)
    ratio = cap;
  Else
    lo = 1; hi = cap;
    For k In {1:60}
      mid = 0.5 * (lo + hi);
      If (W * (mid - 1) / (mid^n_conf_r - 1) > first)
        lo = mid;
      Else
        hi = mid;
      EndIf
    EndFor
    ratio = 0.5 * (lo + hi);
  EndIf
EndIf

// cone and flyer (they share the impact face z = 0 and are tied there)
Point(1) = {0, 0, 0}; Point(2) = {Rb, 0, 0}; Point(3) = {Rt, L, 0}; Point(4) = {0, L, 0};
Point(5) = {0, -H, 0}; Point(6) = {Rb, -H, 0};
Line(1) = {1, 2};  // impact face
Line(2) = {2, 3};  // cone side
Line(3) = {3, 4};  // cone rear face
Line(4) = {4, 1};  // axis (cone)
Line(5) = {5, 6};  // flyer back
Line(6) = {6, 2};  // flyer side
Line(7) = {1, 5};  // axis (flyer)
Curve Loop(1) = {1, 2, 3, 4};   Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, -1, 7};  Plane Surface(2) = {2};

// confinement
Point(11) = {Rb, -B, 0}; Point(12) = {Ro, -B, 0}; Point(13) = {Ro, L, 0}; Point(14) = {Rt, L, 0};
Point(15) = {Rb, 0, 0};
Line(11) = {11, 12};  // front face
Line(12) = {12, 13};  // outer surface
Line(13) = {14, 13};  // rear face
Line(14) = {14, 15};  // bore
Line(15) = {15, 11};  // barrel
Curve Loop(3) = {11, 12, -13, 14, 15};  Plane Surface(3) = {3};

Transfinite Curve{1, 3, 5} = n_cone_r + 1;
Transfinite Curve{2, 4} = n_iface + 1;
Transfinite Curve{6, 7} = n_flyer_z + 1;
Transfinite Curve{11, 13} = n_conf_r + 1 Using Progression ratio;
Transfinite Curve{12} = n_guide + m_barrel + 1;
Transfinite Curve{14} = n_guide + 1;
Transfinite Curve{15} = m_barrel + 1;
Transfinite Surface{1} = {1, 2, 3, 4};
Transfinite Surface{2} = {5, 6, 2, 1};
Transfinite Surface{3} = {11, 12, 13, 14};
Recombine Surface{1, 2, 3};

Physical Surface("cone") = {1};
Physical Surface("flyer") = {2};
Physical Surface("confinement") = {3};
Physical Curve("impact") = {1};        // cone base = flyer front (tied)
Physical Curve("cone_side") = {2};     // slave of the cone_wall slide line
Physical Curve("axis") = {4, 7};
Physical Curve("flyer_side") = {6};    // slave of the barrel slide line
Physical Curve("bore") = {14, 15};     // guide of both slide lines (bore + barrel)
Physical Point("cone_fs") = {4};       // free surface of the cone on the axis
