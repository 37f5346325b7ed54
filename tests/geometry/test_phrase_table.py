"""The request's syntax, as a table: for each phrase the object's head noun, its noun phrase (the head with its
compounds), the portion ('slice of'), the states ('rolled up'), the shape phrase's words, the material class and
the colour per part. Words outside the object's own phrase ('lying on its belly', 'in a paper cup') never become
the object."""

from __future__ import annotations

import pytest

from tasks.geometry.concepts import bindings

# text, head, noun phrase, portion, states, shape words, material class ('*': not asserted), colours per part
TABLE = [
    ('a plush giraffe', 'giraffe', 'giraffe', None, [], None, 'plush', {}),
    ('three ripe apples', 'apples', 'apples', None, [], None, None, {}),
    ('two loaves of bread', 'bread', 'bread', 'loaves', [], None, 'bread', {}),
    ('a ball of pizza dough', 'dough', 'pizza dough', 'ball', [], None, 'dough', {}),
    ('a teether ring for a baby', 'ring', 'teether ring', None, [], None, None, {}),
    ('a rubber duckie', 'duck', 'rubber duck', None, [], None, 'rubber', {}),
    ('a squeaky pig dog toy', 'toy', 'squeaky pig dog toy', None, [], None, None, {}),
    ('a yoga mat rolled up', 'mat', 'yoga mat', None, ['rolled'], None, None, {}),
    ('a rolled up yoga mat', 'mat', 'yoga mat', None, ['rolled'], None, None, {}),
    ('a towel folded in half', 'towel', 'towel', None, ['folded'], None, 'textile', {}),
    ('a folded beach towel', 'towel', 'beach towel', None, ['folded'], None, 'textile', {}),
    ('a stack of pancakes', 'pancakes', 'pancakes', 'stack', ['stacked'], None, None, {}),
    ('a stacked pile of washcloths', 'washcloths', 'washcloths', 'pile', ['stacked'], None, None, {}),
    ('a seal pup lying on its belly', 'pup', 'seal pup', None, ['lying'], None, None, {}),
    ('a sleeping puppy curled up on a cushion', 'puppy', 'puppy', None, ['lying', 'curled'], None, 'pu_foam', {}),
    ('a teddy bear sitting on a shelf', 'bear', 'teddy bear', None, ['sitting'], None, 'plush', {}),
    ('an IV fluid bag', 'bag', 'fluid bag', None, [], None, None, {}),
    ('a faded tennis ball the dog found', 'ball', 'faded tennis ball', None, [], None, '*', {}),
    ('a scarf my gran knitted', 'scarf', 'scarf', None, [], None, '*', {}),
    ('a saline bag hanging from a hook', 'bag', 'saline bag', None, ['hung'], None, None, {}),
    ('a hockey-puck-like disc', 'disc', 'disc', None, [], 'hockey puck', None, {}),
    ('a sponge-like foam block', 'block', 'foam block', None, [], 'sponge', 'pu_foam', {}),
    ('a slice of swiss cheese', 'cheese', 'swiss cheese', 'slice', [], None, None, {}),
    ('a wedge of cheddar', 'cheddar', 'cheddar', 'wedge', [], None, 'cheese', {}),  # the cheese class (#39)
    ('a sheet of felt', 'felt', 'felt', 'sheet', [], None, None, {}),
    ('a strip of bacon', 'bacon', 'bacon', 'strip', [], None, None, {}),
    ('a lump of clay', 'clay', 'clay', 'lump', [], None, None, {}),
    ('a cube of tofu', 'tofu', 'tofu', 'cube', [], None, 'gel', {}),
    ('a block of firm tofu', 'tofu', 'tofu', 'block', [], None, 'gel', {}),
    ('a pair of wool socks', 'socks', 'socks', 'pair', [], None, 'textile', {}),
    ('a baking mold shaped like a heart', 'mold', 'baking mold', None, [], 'heart', None, {}),
    ('a cushion shaped like a cat', 'cushion', 'cushion', None, [], 'cat', 'pu_foam', {}),
    ('a pillow in the shape of a star', 'pillow', 'pillow', None, [], 'star', 'pu_foam', {}),
    ('a star-shaped stress ball', 'ball', 'stress ball', None, [], 'star', None, {}),
    ('a heart shaped pillow', 'pillow', 'pillow', None, [], 'heart', 'pu_foam', {}),
    ('a cat pillow', 'pillow', 'cat pillow', None, [], None, 'pu_foam', {}),
    ('an orange cushion', 'cushion', 'cushion', None, [], None, 'pu_foam', {'body': 'orange'}),
    ('a red apple with a green leaf', 'apple', 'apple', None, [], None, None, {'body': 'red', 'leaf': 'green'}),
    ('a white plush bunny with pink ears', 'bunny', 'bunny', None, [], None, 'plush', {'body': 'white', 'ears': 'pink'}),
    ('a blue elephant plush', 'elephant', 'elephant', None, [], None, 'plush', {'body': 'blue'}),
    ('a yellow plush whale', 'whale', 'whale', None, [], None, 'plush', {'body': 'yellow'}),
    ('a green frog with yellow spots', 'frog', 'frog', None, [], None, None, {'body': 'green', 'spots': 'yellow'}),
    ('a hollow rubber ball', 'ball', 'rubber ball', None, ['hollow'], None, 'rubber', {}),
    ('a stuffed owl', 'owl', 'owl', None, ['stuffed'], None, 'plush', {}),
    ('a stuffed toy dinosaur with big teeth', 'dinosaur', 'dinosaur', None, ['stuffed'], None, 'plush', {}),
    ('a plush dinosaur, 30 cm long', 'dinosaur', 'dinosaur', None, [], None, 'plush', {}),
    ('a foam banana toy, 20 cm long', 'toy', 'foam banana toy', None, [], None, 'pu_foam', {}),
    ('a soft silicone spatula', 'spatula', 'silicone spatula', None, [], None, 'silicone', {}),
    ('a silicone baking mat', 'mat', 'silicone baking mat', None, [], None, 'silicone', {}),
    ('a memory foam pillow', 'pillow', 'memory foam pillow', None, [], None, 'pu_foam', {}),
    ('a firm rubber dog ball', 'ball', 'rubber dog ball', None, [], None, 'rubber', {}),
    ('a bouncy rubber ball', 'ball', 'rubber ball', None, [], None, 'rubber', {}),
    ('a squishy foam cube', 'cube', 'squishy foam cube', None, [], None, 'pu_foam', {}),
    ('a latex glove', 'glove', 'glove', None, [], None, 'rubber', {}),
    ('a knitted wool mitten', 'mitten', 'mitten', None, [], None, None, {}),
    ('a fleece blanket folded into a square', 'blanket', 'blanket', None, ['folded'], None, 'textile', {}),
    ('a rolled sleeping bag', 'bag', 'bag', None, ['rolled'], None, None, {}),
    ('a deflated beach ball', 'ball', 'beach ball', None, ['deflated'], None, 'inflatable', {}),
    ('a half inflated balloon', 'balloon', 'balloon', None, ['inflated'], None, 'inflatable', {}),
    ('an empty water bottle', 'bottle', 'water bottle', None, ['hollow'], None, None, {}),
    ('a crumpled paper towel', 'towel', 'paper towel', None, ['crumpled'], None, 'textile', {}),
    ('a bath sponge with a loop', 'sponge', 'sponge', None, [], None, 'sponge', {}),
    ('a loofah', 'loofah', 'loofah', None, [], None, None, {}),
    ('a kitchen sponge with a scrubbing side', 'sponge', 'sponge', None, [], None, 'sponge', {}),
    ('a chocolate muffin', 'muffin', 'muffin', None, [], None, 'bread', {'body': 'chocolate'}),
    ('a blueberry muffin in a paper cup', 'muffin', 'blueberry muffin', None, [], None, 'bread', {}),
    ('a strawberry jelly', 'jelly', 'strawberry jelly', None, [], None, 'gel', {}),
    ('a lemon cake slice', 'slice', 'cake slice', None, [], None, 'bread', {'body': 'lemon'}),
    ('a bunch of grapes', 'grapes', 'grapes', 'bunch', [], None, None, {}),
    ('a croissant on a plate', 'croissant', 'croissant', None, [], None, None, {}),
    ('a dog toy shaped like a bone', 'toy', 'dog toy', None, [], 'bone', None, {}),
    ('a rope toy for dogs', 'toy', 'rope toy', None, [], None, None, {}),
    ('a tennis ball', 'ball', 'tennis ball', None, [], None, None, {}),
    ('a soccer ball', 'ball', 'soccer ball', None, [], None, None, {}),
    ('a stress ball', 'ball', 'stress ball', None, [], None, None, {}),
    ('the squishy thing you squeeze when stressed', 'thing', 'squishy thing', None, [], None, None, {}),
    ('something soft and round', 'something', 'something', None, [], None, None, {}),
    ('a giant jellyfish plush with long tentacles', 'plush', 'jellyfish plush', None, [], None, 'plush', {}),
    ('a small octopus toy with curly legs', 'toy', 'octopus toy', None, [], None, None, {}),
    ('a plush turtle toy, about 25 cm long', 'toy', 'turtle toy', None, [], None, 'plush', {}),
    ('an 8-cm-tall plush cat', 'cat', 'cat', None, [], None, 'plush', {}),
    ('a 1 litre hot water bottle', 'bottle', 'hot water bottle', None, [], None, None, {}),
    ('a 12 oz boxing glove', 'glove', 'boxing glove', None, [], None, None, {}),
    ('a rolled-up elastic bandage', 'bandage', 'elastic bandage', None, ['rolled'], None, None, {}),
    ('a wet sponge', 'sponge', 'wet sponge', None, [], None, 'sponge', {}),
    ('a gel ice pack', 'pack', 'gel ice pack', None, [], None, 'gel', {}),
    ('a bean bag chair', 'chair', 'bean bag chair', None, [], None, None, {}),
    ('a bag of frozen peas', 'bag', 'bag', None, [], None, None, {}),
    ('a dumpling', 'dumpling', 'dumpling', None, [], None, None, {}),
    ('a sushi roll', 'roll', 'sushi roll', None, [], None, 'bread', {}),
    ('a marshmallow', 'marshmallow', 'marshmallow', None, [], None, 'marshmallow', {}),
    ('a piece of bread', 'bread', 'bread', 'piece', [], None, 'bread', {}),
    ('a burrito wrapped in foil', 'burrito', 'burrito', None, [], None, None, {}),
    ('a stuffed crust pizza slice', 'slice', 'crust pizza slice', None, ['stuffed'], None, '*', {}),
    ('a hamster lying on its back', 'hamster', 'hamster', None, ['lying'], None, None, {}),
]


def test_the_table_is_large_enough() -> None:
    assert len(TABLE) >= 80 and len({row[0] for row in TABLE}) == len(TABLE)


@pytest.mark.parametrize("text, head, noun_phrase, portion, states, shape, material, colors", TABLE)
def test_phrase_bindings(text: str, head: str, noun_phrase: str, portion: str | None, states: list[str],
                         shape: str | None, material: str | None, colors: dict[str, str]) -> None:
    b = bindings(text)
    assert (b.head, b.noun_phrase, b.portion) == (head, noun_phrase, portion), text
    assert b.states == states, text
    assert b.shape == shape, text
    if material != "*":
        assert b.material == material, text
    assert b.colors == colors, text
