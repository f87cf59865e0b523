// The bar of bar.geo meshed by a regular 12 x 4 grid of squares (same
// Physical Curves): the regular connectivity of thesis Fig. 4.25.
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
Transfinite Curve {1, 3} = 13;
Transfinite Curve {2, 4} = 5;
Transfinite Surface {1};
Recombine Surface {1};
Physical Curve(1) = {1};
Physical Curve(2) = {3};
Physical Curve(3) = {2};
Physical Curve(4) = {4};
Physical Surface(1) = {1};
