"""Catalogued submissions of each graded chapter, correct and wrong (the instructor's:
see variant.py). CATALOGUE maps a chapter's number to its variants: catalogue.py's
chapters graded by statistics or by their tree, image_chapters.py's graded by their
pictures (03-08), denoising.py's denoiser (28) and temporal.py's blend (29), which
add to the same dictionary."""

from grading_catalogue import denoising, image_chapters, temporal
from grading_catalogue.catalogue import CATALOGUE
from grading_catalogue.variant import Edit, Variant, apply, heading_anchor, solution

__all__ = ["CATALOGUE", "Edit", "Variant", "apply", "denoising", "heading_anchor",
           "image_chapters", "solution", "temporal"]
