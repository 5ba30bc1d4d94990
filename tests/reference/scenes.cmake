# One line per gallery scene:  NAME  SCENE  FRAME  WIDTH  HEIGHT  SAMPLES
lray_reference_test(ring        scenes/ring.lua        2 160 120 2)
lray_reference_test(point_light scenes/point_light.lua 0 160 120 2)
lray_reference_test(area_light  scenes/area_light.lua  0 160 120 2)
lray_reference_test(shapes      scenes/shapes.lua      0 160 120 2)
lray_reference_test(mesh        scenes/mesh.lua        0 160 120 2)
lray_reference_test(textures    scenes/textures.lua    0 160 120 2)
lray_reference_test(image       scenes/image.lua       0 160 120 2)
lray_reference_test(finish      scenes/finish.lua      0 160 120 2)
