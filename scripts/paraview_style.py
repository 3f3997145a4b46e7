"""The look shared by the ParaView views of docs/VIZ.md (paraview_view_export.py,
paraview_view_sdf.py): scalar bars, plain surfaces, a white background and the camera, and
saving a screenshot under pvbatch."""

from paraview import simple

MESH_COLOUR = [0.85, 0.85, 0.82]
TEXT_COLOUR = [0.1, 0.1, 0.1]


def style_scalar_bar(display, lut, view, title):
    """Shows `display`'s scalar bar for `lut` with `title`, in dark text at the upper right.
    Returns the bar, for further settings."""
    display.SetScalarBarVisibility(view, True)
    bar = simple.GetScalarBar(lut, view)
    bar.Title = title
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = TEXT_COLOUR
    bar.TitleFontSize = bar.LabelFontSize = 14
    bar.WindowLocation = "Upper Right Corner"
    return bar


def show_plain(source, view, colour=MESH_COLOUR):
    """Shows `source` in one solid colour (a light grey by default, for meshes)."""
    display = simple.Show(source, view)
    simple.ColorBy(display, None)
    display.AmbientColor = display.DiffuseColor = colour
    return display


def frame(view, azimuth, elevation, dolly):
    """A white background without the orientation axes, and the camera turned by `azimuth`
    and `elevation` degrees from ParaView's default, then moved in by `dolly`."""
    view.Background = [1.0, 1.0, 1.0]
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    view.OrientationAxesVisibility = 0
    view.ResetCamera()
    camera = view.GetActiveCamera()
    camera.Azimuth(azimuth)
    camera.Elevation(elevation)
    view.ResetCamera()
    camera.Dolly(dolly)


def plain_arguments(argv):
    """The script's own arguments: the GUI's sys.argv holds its options (--script=...) too."""
    return [a for a in argv[1:] if not a.startswith("-")]


def save_or_render(view, screenshot, size=(1000, 680)):
    """Saves the view to `screenshot` (a PNG) and closes it, or renders it when `screenshot`
    is None (in the GUI)."""
    if not screenshot:
        simple.Render(view)
        return
    view.ViewSize = list(size)
    simple.SaveScreenshot(screenshot, view, ImageResolution=list(size), CompressionLevel="9")
    # pvbatch exits with status 1 (a GLX error) if a render view is still open at exit.
    simple.Delete(view)
