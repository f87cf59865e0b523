// A bar [0, 3] x [0, 1]: bottom (Physical Curve 1) clamped, top (2)
// pressed, right side (3) the target, left side (4) free.
SetFactory("Built-in");
Point(1) = {0, 0, 0};
Point(2) = {3, 0, 0};
Point(3) = {3, 1, 0};
Point(4) = {0, 1, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve(1) = {1};
Physical Curve(2) = {3};
Physical Curve(3) = {2};
Physical Curve(4) = {4};
Physical Surface(1) = {1};
