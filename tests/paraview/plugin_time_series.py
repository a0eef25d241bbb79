"""The plugin follows ParaView's time: a time series (.pvd) of three steps, whose field is the
wavelet's scaled by 0.6, 1 and 1.4, drawn at each step's time through the plugin, gives at each
step the image `prismoid render --time-step N` gives of that step, and the CPU reference's, within
the bound of plugin_matches_render.py (2 levels: ParaView's 8-bit framebuffer). The transfer
function's range is the first step's throughout, so the steps look different; a plugin that kept
the first step's mesh would match only the first. The steps share their points and cells, so the
mesh is uploaded once and each later step sends its fields alone (counted by the plugin).
"""
import pvtest

BOUND = 2.0
SCALES = [0.6, 1.0, 1.4]
TIMES = [0.0, 0.5, 2.0]


def main():
    a, out, vtu, tf = pvtest.start()
    pvd = pvtest.write_series(vtu, out, SCALES, TIMES)
    pvtest.check_steps(a, pvtest.Scene(pvd), pvd, tf, out, TIMES, BOUND)
    print("PASS")


main()
