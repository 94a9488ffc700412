"""Does every label of the Moldtex panels fit at the sidebar's default width? (no test
cases here: used by test_ui.py in background mode and by gui_panel.py in Blender's
interface under Xvfb).

The panels' draw() runs against GeometryLayout, which follows the width each item gets
the way Blender's layout engine hands it out, and measures each label with blf (the
interface's font): a label wider than its room is shown cut ("Movem…").

The geometry, in pixels at an interface scale of 1 (constants measured on Blender 3.4's
sidebar at its default width, where the region is 229 px wide at the scale 1.04 that
Xvfb gives; see gui_panel.py's screenshot):
  - CONTENT: the width of a panel's layout at the default sidebar width (region width
    less the category tabs and the panel margins): 166 px;
  - a box takes BOX_MARGIN on each side;
  - property split: the label column takes SPLIT of the row (less the decorator column
    when decorators are on), and its text has TEXT_PAD less (margins either side);
  - a plain label has ICON px less for its icon and LABEL_PAD for its margins (the
    screenshot shows "Moldtex core 0.1.0 (ABI 1)", 133 px, whole beside an icon).
Checked against the screenshot of the old layout: it cuts "Turn Speed" (55 px at font
size 11) and "Evaporation" (59 px) in a split column with decorators, and shows
"Substeps" (44 px) whole; "Collection" (50 px) is cut in a box. Blender 4.0+ draw
with another font (Inter, a little wider) and about the same layout; there the check
measures with that font and the same geometry (no interface here to screenshot them).
"""

import blf
import bpy

CONTENT = 166.0
BOX_MARGIN = 5.0
SPLIT = 0.435
DECORATOR = 20.0
TEXT_PAD = 15.0
LABEL_PAD = 8.0
ICON = 20.0
SAFETY = 2.0  # px of room each label keeps (rounding, other fonts' hinting)
FONT_SIZE = 11


def set_font_size(scale=1.0):
    try:
        blf.size(0, FONT_SIZE * scale, 72)  # Blender < 4.0
    except TypeError:
        blf.size(0, FONT_SIZE * scale)


def fonts_work():
    """blf measures text with the interface's font (it does in background mode too,
    once a size is set; a build without fonts would measure 0)."""
    set_font_size()
    return blf.dimensions(0, "Evaporation")[0] > 20.0


def text_width(text):
    return blf.dimensions(0, text)[0]


class GeometryLayout:
    """Stands in for bpy.types.UILayout; records (kind, text, room in px) of every label
    it would draw."""

    def __init__(self, log, width, depth=0):
        self.log = log
        self.width = width
        self.depth = depth
        self.use_property_split = False
        self.use_property_decorate = True
        self.scale_y = 1.0
        self.enabled = True
        self.active = True
        self.alert = False
        self.emboss = 'NORMAL'
        self._row = False

    def _child(self, width=None, depth=None, row=False):
        child = GeometryLayout(self.log, self.width if width is None else width,
                               self.depth if depth is None else depth)
        child.use_property_split = self.use_property_split
        child.use_property_decorate = self.use_property_decorate
        child._row = row
        return child

    def column(self, **kwargs):
        return self._child()

    def row(self, **kwargs):
        return self._child(row=True)

    def box(self):
        return self._child(width=self.width - 2 * BOX_MARGIN, depth=self.depth + 1)

    def split(self, factor=0.5, **kwargs):
        return self._child(width=self.width * factor)

    def grid_flow(self, columns=0, **kwargs):
        return self._child(width=self.width / max(1, columns))

    def separator(self, **kwargs):
        pass

    def _record(self, kind, text, room):
        if text:
            self.log.append((kind, text, room))

    def label(self, text="", icon='NONE', **kwargs):
        room = self.width - LABEL_PAD - (ICON if icon != 'NONE' else 0)
        self._record("label", text, room)

    def _prop_label(self, data, name, text, expand=False):
        prop = data.bl_rna.properties[name]
        label = prop.name if text is None else text
        if prop.type == 'BOOLEAN' and not self.use_property_split:
            self._record("checkbox", label, self.width - TEXT_PAD - ICON)
            return
        if self._row:
            return  # buttons in a row: values only in this panel (text="" or icons)
        if self.use_property_split:
            row = self.width - (DECORATOR if self.use_property_decorate else 0)
            if getattr(prop, "is_array", False) and prop.subtype in ('XYZ', 'TRANSLATION',
                                                                     'DIRECTION', 'EULER'):
                label = f"{label} X"  # a vector's first row says its axis ("Direction X")
            self._record("prop", label, SPLIT * row - TEXT_PAD)
        elif not expand:
            # Without split a label sits left of its value, half the row each.
            self._record("prop", label, self.width / 2 - TEXT_PAD)

    def prop(self, data, name, text=None, expand=False, **kwargs):
        self._prop_label(data, name, text, expand)

    def prop_search(self, data, name, search_data, search_name, text=None, **kwargs):
        self._prop_label(data, name, text)

    def operator(self, idname, text=None, **kwargs):
        return _AnyProps()

    def menu(self, idname, text="", **kwargs):
        pass


class _AnyProps:
    def __setattr__(self, name, value):
        pass


def draw_panels(context, width=CONTENT):
    """[(kind, text, room)] of every label the Moldtex panels draw for context."""
    from moldtex.ui import panels as ui
    log = []
    for panel in ui.CLASSES:
        if hasattr(panel, "poll") and not panel.poll(context):
            continue
        layout = GeometryLayout(log, width)
        panel.draw(_Panel(layout), context)
    return log


class _Panel:
    def __init__(self, layout):
        self.layout = layout


def labels_cut(context, scale=1.0):
    """[(text, width, room)] of the labels that would not fit, in px at the font size
    of interface scale `scale` (the layout scales with it)."""
    set_font_size(scale)
    cut = []
    for kind, text, room in draw_panels(context, CONTENT * scale):
        width = text_width(text)
        if width > room - SAFETY * scale:
            cut.append((text, round(width, 1), round(room, 1)))
    set_font_size()
    return cut


def busy_scene_states():
    """Yields after setting up, in turn, panel states that show the most rows (for
    every check to see every label): the caller draws the panels at each."""
    obj = bpy.context.active_object
    settings = obj.moldtex
    brush = bpy.context.scene.moldtex_brush
    for shape in ('STARBURST', 'CIRCLE', 'SPAWN_MAP'):
        settings.seed_shape = shape
        for source in ('IMAGE', 'ATTRIBUTES'):
            settings.fields_source = source
            settings.species_count = 2
            for target in ('OBSTACLE', 'SLIME', 'FOOD'):
                brush.target = target
                settings.bake_use_scene_range = target != 'SLIME'
                yield f"{shape}/{source}/{target}"
    settings.species_count = 1
    settings.seed_shape = 'RANDOM'
    settings.fields_source = 'IMAGE'
    brush.target = 'OBSTACLE'
    settings.bake_use_scene_range = True
    # The continuous model's panels: both pattern scale modes, turnover off and on, a
    # negative sensor angle (its note), several species (their note), a PNG bake (the
    # clipping note), the bias off and on (its notes).
    settings.model = 'CONTINUOUS'
    cont = settings.continuous
    for mode in ('OBJECT', 'LENGTH'):
        settings.pattern_scale_mode = mode
        for lifetime, angle in ((0.0, 0.5), (1.0, -0.5)):
            cont.mean_lifetime = lifetime
            cont.sensor_angle = angle
            settings.species_count = 2 if lifetime else 1
            settings.bake_format = 'PNG8' if lifetime else 'EXR_HALF'
            cont.bias_strength = 4.0 if lifetime else 0.0  # the Bias panel's two notes
            yield f"CONTINUOUS/{mode}/lifetime {lifetime}"
    # The Maps panel with every map on: groups and images, and one with nothing picked
    # (its note).
    slots = [getattr(settings.maps, p.identifier) for p in settings.maps.bl_rna.properties
             if p.identifier not in {"rna_type", "name"}]
    for index, slot in enumerate(slots):
        slot.enabled = True
        slot.source = 'IMAGE' if index % 2 else 'ATTRIBUTE'
        slot.attribute = "Group" if index else ""
    settings.domain = 'INTRINSIC'  # the Domain row and Triangle Size (Simulation panel)
    yield "CONTINUOUS/maps"
    # Gray-Scott: its Reaction panel, its three maps on, the Species & Start note and
    # the slime brush's note.
    settings.model = 'GRAY_SCOTT'
    brush.target = 'SLIME'
    yield "GRAY_SCOTT/maps"
    brush.target = 'OBSTACLE'
    for slot in slots:
        slot.enabled = False
        slot.attribute = ""
    settings.domain = 'TEXTURE'
    settings.model = 'MOMAS'
    settings.pattern_scale_mode = 'OBJECT'
    settings.species_count = 1
    settings.bake_format = 'EXR_HALF'
    cont.mean_lifetime = 0.0
    cont.sensor_angle = 0.5
    cont.bias_strength = 0.0
