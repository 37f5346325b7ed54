"""Session 36's third batch of lexicon objects (food and shops, office and school: the bakery and cafe counter,
sweets, street food, packaged supermarket goods, the pet shop, the first-aid shelf, the classroom and the desk), which
L0 built as something else (a generic block, a plush dog for 'corn dog', a garment for 'crepe'): each is found by a
natural phrasing other than its first noun and, built at draft, weighs within 2x of the real object."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "entry"), [
    ("a corndog on a stick", "corn_dog"),  # 'corn dog' was a plush dog
    ("a sicilian cannoli", "cannoli"),  # a generic block
    ("a hanami dango skewer", "dango"),
    ("a chocolate whoopie pie", "whoopie_pie"),  # a pie
    ("an egg over easy", "fried_egg"),  # 'fried egg' was a boiled egg
    ("a vanilla soft serve cone", "soft_serve_cone"),
    ("a toasted s'more", "smore"),
    ("a nutella crepe", "crepe"),  # 'crepe' was a generic garment (crepe fabric)
    ("a cheese quesadilla", "quesadilla"),
    ("a chicken shawarma wrap", "gyro_wrap"),  # 'doner wrap' was a naan bread
    ("a boat of takoyaki", "takoyaki"),
    ("a vietnamese sandwich", "banh_mi"),  # a ham sandwich
    ("a frosted pop tart", "toaster_pastry"),  # 'pop tart' was a pie
    ("a puff pastry cream horn", "cream_horn"),
    ("a carton of fries", "french_fries"),  # a generic bag; 'fries' a generic round fruit
    ("a blue freeze pop", "freeze_pop"),
    ("a dog snuffle mat", "snuffle_mat"),
    ("a felted cat cave", "cat_cave"),
    ("a band-aid", "adhesive_bandage"),
    ("a q-tip", "cotton_swab"),
    ("a travel first aid kit", "first_aid_kit"),  # 'first aid pouch' was a drawstring pouch
    ("a doctor's stethoscope", "stethoscope"),
    ("an insulated lunch bag", "lunch_box"),  # a paper lunch bag
    ("a pack of frozen peas", "frozen_peas"),  # a generic pouch
    ("a bag of milk", "milk_bag"),  # a generic pouch
    ("a fresh tagliatelle nest", "pasta_nest"),
    ("a pon de ring", "mochi_donut"),  # 'mochi donut' was a plain donut
])
def test_s36c_nouns_build_their_own_object(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize(("text", "real"), [
    ("a corn dog", 0.08),  # ~45 g frankfurter in ~35 g of batter (frozen corn dogs 70-85 g)
    ("a cannoli", 0.07),  # ~15 g shell, ~55 g ricotta (bakery cannoli 50-90 g)
    ("a dango", 0.05),  # three 3.2 cm rice-flour balls on a skewer
    ("a whoopie pie", 0.1),  # 3-4 oz (85-113 g)
    ("a fried egg", 0.046),  # USDA: one large fried egg 46 g
    ("a soft serve cone", 0.12),  # small cones 100-140 g
    ("a smore", 0.035),  # two graham squares, a marshmallow, a piece of chocolate
    ("a crepe", 0.075),  # ~55 g crepe with ~20 g of chocolate spread
    ("a quesadilla", 0.2),  # 10 in tortilla (~70 g) over ~130 g of cheese and filling
    ("a gyro", 0.32),  # takeaway gyros 280-400 g
    ("a takoyaki", 0.14),  # six ~22 g balls in a paper boat
    ("a banh mi", 0.28),  # ~90 g baguette, ~190 g filling
    ("a toaster pastry", 0.05),  # 48-52 g per pastry
    ("a cream horn", 0.06),  # bakery cream horns 45-75 g
    ("french fries", 0.12),  # medium serving 110-117 g plus the carton
    ("a freeze pop", 0.045),  # 1-2 fl oz (30-60 g)
    ("a snuffle mat", 0.4),  # 40 x 30 cm, 300-500 g
    ("a cat cave", 0.9),  # felted wool, 0.7-1.1 kg
    ("an adhesive bandage", 0.0003),  # ~0.3 g
    ("a cotton swab", 0.00036),  # ~0.36 g
    ("a first aid kit", 0.4),  # filled soft kits 0.3-0.5 kg
    ("a stethoscope", 0.13),  # acoustic stethoscopes 100-190 g
    ("a lunch box", 0.35),  # insulated soft lunch boxes, empty, 0.3-0.45 kg
    ("a bag of frozen peas", 0.454),  # 16 oz bag
    ("a milk bag", 1.37),  # a 1.33 l Canadian milk bag
    ("a pasta nest", 0.062),  # a 250 g pack holds four nests
    ("a mochi donut", 0.048),  # eight fried dough balls in a ring
])
def test_s36c_masses_within_2x(text: str, real: float) -> None:
    assert 0.5 * real <= planned_mass(text) <= 2.0 * real
