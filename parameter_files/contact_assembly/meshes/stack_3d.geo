// Two stacked unit-square blocks sharing the plane z = 0.5 (materials 1 and
// 2), hexahedra. gmsh -3 -format msh2 stack_3d.geo -o stack_3d.msh
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 0.5};
Box(2) = {0, 0, 0.5, 1, 1, 0.5};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Transfinite Curve{:} = 3;
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{:};
e = 1e-6;
Physical Volume(1) = Volume In BoundingBox{-e, -e, -e, 1 + e, 1 + e, 0.5 + e};
Physical Volume(2) = Volume In BoundingBox{-e, -e, 0.5 - e, 1 + e, 1 + e, 1 + e};
Physical Surface(2) = Surface In BoundingBox{-e, -e, -e, 1 + e, 1 + e, e};
Physical Surface(3) = Surface In BoundingBox{-e, -e, 1 - e, 1 + e, 1 + e, 1 + e};
Physical Surface(4) = Surface In BoundingBox{-e, -e, -e, e, 1 + e, 1 + e};
Physical Surface(6) = Surface In BoundingBox{-e, -e, -e, 1 + e, e, 1 + e};
Physical Surface(5) = Surface In BoundingBox{1 - e, -e, -e, 1 + e, 1 + e, 1 + e};
Physical Surface(7) = Surface In BoundingBox{-e, 1 - e, -e, 1 + e, 1 + e, 1 + e};
