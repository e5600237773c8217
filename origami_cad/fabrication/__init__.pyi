"""The names of the package, each imported on first use (origami_cad._lazy.attach_stub)."""

from origami_cad.fabrication.build import (
    Fabrication,
    FabricationFiles,
    build_fabrication,
    fabricate,
    fabrication_numbers,
    write_fabrication,
)
from origami_cad.fabrication.panels import (
    PanelOutline,
    offset_ring,
    panel_outlines,
    plan_holes,
)
from origami_cad.fabrication.params import (
    DENSITY_G_CM3,
    FabricationParams,
    bias_for_p_max,
    bias_for_theta_max,
    fabrication_params,
    theta_max,
)
from origami_cad.fabrication.plan import (
    DEFAULT_BED,
    CreaseLimits,
    LimitStatus,
    PanelPlan,
    check_bed,
    check_panel_count,
    crease_limits,
    largest_bias,
    plan_panels,
)
