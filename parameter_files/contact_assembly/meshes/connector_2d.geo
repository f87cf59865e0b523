// A 2D connector (thesis Fig. 2.9): a base (material 1) with a slot and a
// cap (material 2) whose peg fills the slot; they share the slot walls, the
// slot bottom and the base top under the cap. Triangles.
// gmsh -2 -format msh2 connector_2d.geo -o connector_2d.msh
// Element size h, peg width w and slot depth d: gmsh -setnumber h 0.05 ...
// (w = 1 is the wide peg of doc/contact_assembly.md's comparison).
DefineConstant[ h = 0.1, w = 0.4, d = 0.6 ];
Point(1) = {0, 0, 0, h};           Point(2) = {3, 0, 0, h};
Point(3) = {3, 1, 0, h};           Point(4) = {2.5, 1, 0, h};
Point(5) = {1.5 + w / 2, 1, 0, h}; Point(6) = {1.5 + w / 2, 1 - d, 0, h};
Point(7) = {1.5 - w / 2, 1 - d, 0, h}; Point(8) = {1.5 - w / 2, 1, 0, h};
Point(9) = {0.5, 1, 0, h};   Point(10) = {0, 1, 0, h};
Point(11) = {2.5, 1.5, 0, h}; Point(12) = {0.5, 1.5, 0, h};
Line(1) = {1, 2};   Line(2) = {2, 3};   Line(3) = {3, 4};  Line(4) = {4, 5};
Line(5) = {5, 6};   Line(6) = {6, 7};   Line(7) = {7, 8};  Line(8) = {8, 9};
Line(9) = {9, 10};  Line(10) = {10, 1};
Line(11) = {4, 11}; Line(12) = {11, 12}; Line(13) = {12, 9};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
Plane Surface(1) = {1};
Curve Loop(2) = {-8, -7, -6, -5, -4, 11, 12, 13};
Plane Surface(2) = {2};
Physical Curve(1) = {1};                  // base bottom: clamped
Physical Curve(3) = {12};                 // cap top: loaded
Physical Curve(2) = {2, 3, 9, 10, 11, 13}; // free sides
Physical Surface(1) = {1};
Physical Surface(2) = {2};
