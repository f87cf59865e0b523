// A four-legged stool (thesis Fig. 2.24), one quarter by its two mirror
// planes x = 0 and y = 0: an MDF seat (material 3) rests on a PLA
// connector (material 1) whose socket holds a wooden leg (material 2)
// standing on the floor. The parts share their contact surfaces
// (fragments), so the mesh is conforming across them. Tetrahedra.
// gmsh -3 -format msh2 stool_quarter_3d.geo -o stool_quarter_3d.msh
SetFactory("OpenCASCADE");
DefineConstant[ h = 0.25 ];
Box(1) = {0, 0, 3, 2.5, 2.5, 0.3};            // seat quarter
Box(2) = {0.8, 0.8, 2.2, 1.6, 1.6, 0.8};      // connector block
Cylinder(3) = {1.6, 1.6, 0, 0, 0, 2.8, 0.4};  // leg, up to z = 2.8
BooleanDifference(4) = { Volume{2}; Delete; }{ Volume{3}; };
BooleanFragments{ Volume{1, 4, 3}; Delete; }{}
Mesh.MeshSizeMax = h;
e = 1e-6;
Physical Volume(3) = Volume In BoundingBox{-e, -e, 3 - e, 2.5 + e, 2.5 + e, 3.3 + e};
Physical Volume(1) = Volume In BoundingBox{0.8 - e, 0.8 - e, 2.2 - e, 2.4 + e, 2.4 + e, 3 + e};
Physical Volume(2) = Volume In BoundingBox{1.2 - e, 1.2 - e, -e, 2 + e, 2 + e, 2.8 + e};
// Leg foot: on the floor (rigid contact); seat top: loaded; the seat's
// faces on the mirror planes x = 0 (5) and y = 0 (6).
Physical Surface(1) = Surface In BoundingBox{1.2 - e, 1.2 - e, -e, 2 + e, 2 + e, e};
Physical Surface(3) = Surface In BoundingBox{-e, -e, 3.3 - e, 2.5 + e, 2.5 + e, 3.3 + e};
Physical Surface(5) = Surface In BoundingBox{-e, -e, 3 - e, e, 2.5 + e, 3.3 + e};
Physical Surface(6) = Surface In BoundingBox{-e, -e, 3 - e, 2.5 + e, e, 3.3 + e};
// The connector's free faces (sides and bottom ring): the design surface.
Physical Surface(4) = {
  Surface In BoundingBox{2.4 - e, 0.8 - e, 2.2 - e, 2.4 + e, 2.4 + e, 3 + e},
  Surface In BoundingBox{0.8 - e, 0.8 - e, 2.2 - e, 0.8 + e, 2.4 + e, 3 + e},
  Surface In BoundingBox{0.8 - e, 2.4 - e, 2.2 - e, 2.4 + e, 2.4 + e, 3 + e},
  Surface In BoundingBox{0.8 - e, 0.8 - e, 2.2 - e, 2.4 + e, 0.8 + e, 3 + e},
  Surface In BoundingBox{0.8 - e, 0.8 - e, 2.2 - e, 2.4 + e, 2.4 + e, 2.2 + e}
};
// Everything else on the outside (the seat's outer sides and bottom, the
// leg's shaft): untagged, boundary id 0.
