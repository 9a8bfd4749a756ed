Feature: OBJ files
  Reading Wavefront OBJ text: vertices, vertex normals, faces (fanned out into triangles)
  and named groups, collected into a group that can be added to a world.

  # Any line the parser does not understand is skipped and counted.
  @chapter15
  Scenario: Lines the parser does not understand are skipped
    Given gibberish ← a file containing:
      """
      Nothing written here describes any geometry;
      these are just words that a parser should skip over.
      Each line starts with a word the format does not know,
      so every one is counted and then ignored,
      which makes five lines to ignore in all.
      """
    When parser ← parse_obj_file(gibberish)
    Then parser should have ignored 5 lines

  # Vertices are numbered from 1, in the order they appear.
  @chapter15
  Scenario: Reading vertex lines
    Given file ← a file containing:
      """
      v -1 1 0
      v -1.0000 0.5000 0.0000
      v 1 0 0
      v 1 1 0
      """
    When parser ← parse_obj_file(file)
    Then parser.vertices[1] = point(-1, 1, 0)
      And parser.vertices[2] = point(-1, 0.5, 0)
      And parser.vertices[3] = point(1, 0, 0)
      And parser.vertices[4] = point(1, 1, 0)

  @chapter15
  Scenario: Reading triangular faces
    Given file ← a file containing:
      """
      v -1 1 0
      v -1 0 0
      v 1 0 0
      v 1 1 0

      f 1 2 3
      f 1 3 4
      """
    When parser ← parse_obj_file(file)
      And g ← parser.default_group
      And t1 ← first child of g
      And t2 ← second child of g
    Then t1.p1 = parser.vertices[1]
      And t1.p2 = parser.vertices[2]
      And t1.p3 = parser.vertices[3]
      And t2.p1 = parser.vertices[1]
      And t2.p2 = parser.vertices[3]
      And t2.p3 = parser.vertices[4]

  # A face with more than three vertices becomes a fan of triangles that all share its
  # first vertex.
  @chapter15
  Scenario: A face with five corners becomes three triangles
    Given file ← a file containing:
      """
      v -1 1 0
      v -1 0 0
      v 1 0 0
      v 1 1 0
      v 0 2 0

      f 1 2 3 4 5
      """
    When parser ← parse_obj_file(file)
      And g ← parser.default_group
      And t1 ← first child of g
      And t2 ← second child of g
      And t3 ← third child of g
    Then t1.p1 = parser.vertices[1]
      And t1.p2 = parser.vertices[2]
      And t1.p3 = parser.vertices[3]
      And t2.p1 = parser.vertices[1]
      And t2.p2 = parser.vertices[3]
      And t2.p3 = parser.vertices[4]
      And t3.p1 = parser.vertices[1]
      And t3.p2 = parser.vertices[4]
      And t3.p3 = parser.vertices[5]

  # files/triangles.obj has four vertices, a group FirstGroup holding the face 1 2 3 and a
  # group SecondGroup holding the face 1 3 4.
  @chapter15
  Scenario: Faces are filed under the named group that precedes them
    Given file ← the file "triangles.obj"
    When parser ← parse_obj_file(file)
      And g1 ← "FirstGroup" from parser
      And g2 ← "SecondGroup" from parser
      And t1 ← first child of g1
      And t2 ← first child of g2
    Then t1.p1 = parser.vertices[1]
      And t1.p2 = parser.vertices[2]
      And t1.p3 = parser.vertices[3]
      And t2.p1 = parser.vertices[1]
      And t2.p2 = parser.vertices[3]
      And t2.p3 = parser.vertices[4]

  @chapter15
  Scenario: The parsed file becomes one group holding its named groups
    Given file ← the file "triangles.obj"
      And parser ← parse_obj_file(file)
    When g ← obj_to_group(parser)
    Then g includes "FirstGroup" from parser
      And g includes "SecondGroup" from parser

  # Normals are numbered from 1 like vertices, and are kept exactly as written (not
  # normalized).
  @chapter15
  Scenario: Reading vertex normal lines
    Given file ← a file containing:
      """
      vn 0 0 1
      vn 0.707 0 -0.707
      vn 1 2 3
      """
    When parser ← parse_obj_file(file)
    Then parser.normals[1] = vector(0, 0, 1)
      And parser.normals[2] = vector(0.707, 0, -0.707)
      And parser.normals[3] = vector(1, 2, 3)

  # A face corner is written vertex/texture/normal; the texture index may be left empty
  # (1//3) and is ignored when present. Faces with normals become smooth triangles, so both
  # lines describe the same triangle.
  @chapter15
  Scenario: Faces that name a normal for each corner
    Given file ← a file containing:
      """
      v 0 1 0
      v -1 0 0
      v 1 0 0

      vn -1 0 0
      vn 1 0 0
      vn 0 1 0

      f 1//3 2//1 3//2
      f 1/0/3 2/102/1 3/14/2
      """
    When parser ← parse_obj_file(file)
      And g ← parser.default_group
      And t1 ← first child of g
      And t2 ← second child of g
    Then t1.p1 = parser.vertices[1]
      And t1.p2 = parser.vertices[2]
      And t1.p3 = parser.vertices[3]
      And t1.n1 = parser.normals[3]
      And t1.n2 = parser.normals[1]
      And t1.n3 = parser.normals[2]
      And t2 = t1
