-- time_vs_error bench scene "ring": scenes/ring.lua (Listing 1 of the LRay
-- paper: a ring of 20 spheres, the camera circling it over 20 frames), with
-- the camera's aspect set to the bench's 16:9 instead of the default 1.33.
-- The bench renders one frame of it (run: RING_FRAME). POV-Ray twin: ring.pov.
scene_info = SceneInfo() { image_width = 320, image_height = 180, frames = 20 }
function scene(clock)
    local camera = Perspective(45, 16 / 9) { transform =
        Rotate(y, 360*clock) * Translate(-5*z) }
    local s = Scene() { camera = camera }
    for i = 1,20 do
        local tf = Rotate(z, (i/20)*360) * Translate(x)
            * Scale(.1, .1, .1)
        local sphere = Sphere(tf)
        s:add_entity(sphere)
    end
    s:add_light(Light() { transform = Translate(x - 3*z) })
    return s
end
