Feature: Path tracing
  Beyond the book: the book's materials, lights and shapes rendered the Monte Carlo way. A
  path starts at the camera with a throughput of white; at every hit it adds what the surface
  emits, chooses one of the material's lobes (glass, mirror or diffuse, by their shares),
  scatters, and is multiplied by the lobe's weight; at a diffuse hit it also looks at each of
  the world's lights (one shadow ray each). A path that meets nothing sees the sky. `depth`
  caps the scatter events: at the hit of bounce `depth` only emission counts. Its random
  numbers are a pure function of seed, pixel, sample, bounce and dimension, so a picture
  never depends on who traces it. (Chapter 21 here.)

  # --- random numbers

  @chapter21
  Scenario: A path's random number depends on its arguments alone
    Given u ← path_random(7, 3, 4, 5, 1, 2)
    Then u = path_random(7, 3, 4, 5, 1, 2)
      And u >= 0
      And u < 1

  # Each argument chooses another number: seed, x, y, sample, bounce, dimension.
  @chapter21
  Scenario Outline: Every argument of a path's random number matters
    Given u ← path_random(7, 3, 4, 5, 1, 2)
    Then path_random(<seed>, <x>, <y>, <i>, <bounce>, <dimension>) != u

    Examples:
      | seed | x | y | i | bounce | dimension |
      | 8    | 3 | 4 | 5 | 1      | 2         |
      | 7    | 2 | 4 | 5 | 1      | 2         |
      | 7    | 3 | 5 | 5 | 1      | 2         |
      | 7    | 3 | 4 | 6 | 1      | 2         |
      | 7    | 3 | 4 | 5 | 0      | 2         |
      | 7    | 3 | 4 | 5 | 1      | 3         |

  @chapter21
  Scenario: A path's random numbers lie in [0, 1)
    Given us ← path_random(11, 0, 0, i, 0, 1) for each i from 0 to 999
    Then u >= 0 for each u in us
      And u < 1 for each u in us
      And mean(us) > 0.45
      And mean(us) < 0.55

  # --- where a diffuse bounce goes

  # T and B complete the normal to a right-handed frame; the formula branches only on
  # the sign of n.z (Duff et al. 2017).
  @chapter21
  Scenario Outline: An orthonormal basis around a normal
    Given n ← normalize(<normal>)
    When (t, b) ← orthonormal_basis(n)
    Then magnitude(t) = 1
      And magnitude(b) = 1
      And dot(t, n) = 0
      And dot(b, n) = 0
      And dot(t, b) = 0
      And cross(t, b) = n

    Examples:
      | normal            |
      | vector(0, 0, 1)   |
      | vector(0, 0, -1)  |
      | vector(0, 1, 0)   |
      | vector(1, -2, 3)  |
      | vector(-1, 2, -3) |

  @chapter21
  Scenario: The corners of a cosine-weighted direction's square
    Given n ← vector(0, 1, 0)
    Then cosine_direction(n, 0, 0) = n
      And cosine_direction(n, 0, 0.5) = n
      And cosine_direction(n, 0.5, 0) = vector(√2/2, √2/2, 0)
      And cosine_direction(n, 0.5, 0.25) = vector(0, √2/2, -√2/2)

  @chapter21
  Scenario Outline: Cosine-weighted directions are unit vectors on the normal's side
    Given n ← normalize(<normal>)
    When ds ← cosine_direction(n, path_random(7, 0, 0, i, 0, 3), path_random(7, 0, 0, i, 0, 4)) for each i from 0 to 255
    Then magnitude(d) = 1 for each d in ds
      And dot(d, n) > 0 for each d in ds

    Examples:
      | normal           |
      | vector(0, 1, 0)  |
      | vector(0, 0, -1) |
      | vector(1, -2, 3) |

  # Their density is cos(theta) / pi: the mean cosine is 2/3 and the mean squared cosine
  # 1/2 (uniform directions would give 1/2 and 1/3). The seed is fixed, so this is one
  # set of 4096 directions, the same every run.
  @chapter21
  Scenario: Cosine-weighted directions have the cosine distribution
    Given n ← normalize(vector(1, -2, 3))
    When ds ← cosine_direction(n, path_random(7, 0, 0, i, 0, 3), path_random(7, 0, 0, i, 0, 4)) for each i from 0 to 4095
      And cosines ← dot(d, n) for each d in ds
      And squares ← dot(d, n) * dot(d, n) for each d in ds
    Then mean(cosines) > 2/3 - 0.01
      And mean(cosines) < 2/3 + 0.01
      And mean(squares) > 1/2 - 0.01
      And mean(squares) < 1/2 + 0.01

  # --- which lobe

  # Glass takes a share of transparency, the mirror of reflective, diffuse the rest; when
  # the two add up to more than 1, both are scaled down to share 1.
  @chapter21
  Scenario Outline: A material's lobe is chosen by its share
    Given m ← material()
      And m.reflective ← <reflective>
      And m.transparency ← <transparency>
    Then choose_lobe(m, <u>) = <lobe>

    Examples:
      | reflective | transparency | u     | lobe      |
      | 0          | 0            | 0     | "diffuse" |
      | 0          | 0            | 0.999 | "diffuse" |
      | 1          | 0            | 0     | "mirror"  |
      | 1          | 0            | 0.999 | "mirror"  |
      | 0.3        | 0            | 0.29  | "mirror"  |
      | 0.3        | 0            | 0.31  | "diffuse" |
      | 0          | 1            | 0.999 | "glass"   |
      | 0.2        | 0.5          | 0.49  | "glass"   |
      | 0.2        | 0.5          | 0.51  | "mirror"  |
      | 0.2        | 0.5          | 0.71  | "diffuse" |
      | 0.9        | 0.9          | 0.49  | "glass"   |
      | 0.9        | 0.9          | 0.51  | "mirror"  |
      | 0.9        | 0.9          | 0.999 | "mirror"  |

  # --- scattering at a hit: scatter(comps, lobe_u, fresnel_u, u1, u2)

  @chapter21
  Scenario: A diffuse surface scatters cosine-weighted, tinted by its colour and diffuse
    Given shape ← sphere() with:
      | material.color   | color(0.8, 1.0, 0.6) |
      | material.diffuse | 0.7                  |
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And i ← intersection(4, shape)
    When comps ← prepare_computations(i, r)
      And s ← scatter(comps, 0.5, 0.5, 0.3, 0.6)
    Then s.lobe = "diffuse"
      And s.weight = color(0.56, 0.7, 0.42)
      And s.ray.origin = comps.over_point
      And s.ray.direction = cosine_direction(comps.normalv, 0.3, 0.6)

  @chapter21
  Scenario: A diffuse surface's colour is its pattern's at the point
    Given shape ← sphere() with:
      | material.pattern | stripe_pattern(color(1, 0.5, 0), color(0, 0, 0)) |
      | material.diffuse | 0.5                                              |
      And r ← ray(point(0.5, 0, -5), vector(0, 0, 1))
      And xs ← intersect(shape, r)
    When comps ← prepare_computations(xs[0], r, xs)
      And s ← scatter(comps, 0.5, 0.5, 0.3, 0.6)
    Then s.weight = color(0.5, 0.25, 0)

  # The book's reflections are not tinted by the surface: the mirror's share is its
  # probability, and the path keeps its throughput.
  @chapter21
  Scenario: A mirror scatters along the reflected ray, untinted
    Given shape ← plane() with:
      | material.reflective | 1                    |
      | material.color      | color(0.2, 0.3, 0.4) |
      And r ← ray(point(0, 1, -1), vector(0, -√2/2, √2/2))
      And i ← intersection(√2, shape)
    When comps ← prepare_computations(i, r)
      And s ← scatter(comps, 0.5, 0.5, 0.3, 0.6)
    Then s.lobe = "mirror"
      And s.weight = color(1, 1, 1)
      And s.ray.origin = comps.over_point
      And s.ray.direction = vector(0, √2/2, √2/2)

  # Head on, glass of index 1.5 reflects with Schlick's 0.04: a fresnel number below it
  # reflects, any other refracts, straight through, from under the surface.
  @chapter21
  Scenario Outline: Glass reflects or refracts by Schlick's reflectance
    Given shape ← glass_sphere()
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And xs ← intersections(4:shape, 6:shape)
    When comps ← prepare_computations(xs[0], r, xs)
      And s ← scatter(comps, 0.5, <fresnel_u>, 0.3, 0.6)
    Then s.lobe = <lobe>
      And s.weight = color(1, 1, 1)
      And s.ray.origin = <origin>
      And s.ray.direction = <direction>

    Examples:
      | fresnel_u | lobe      | origin            | direction        |
      | 0.039     | "reflect" | comps.over_point  | vector(0, 0, -1) |
      | 0.041     | "refract" | comps.under_point | vector(0, 0, 1)  |
      | 0.999     | "refract" | comps.under_point | vector(0, 0, 1)  |

  @chapter21
  Scenario: Under total internal reflection glass always reflects
    Given shape ← glass_sphere()
      And r ← ray(point(0, 0, √2/2), vector(0, 1, 0))
      And xs ← intersections(-√2/2:shape, √2/2:shape)
    When comps ← prepare_computations(xs[1], r, xs)
      And s ← scatter(comps, 0.5, 0.999, 0.3, 0.6)
    Then schlick(comps) = 1.0
      And s.lobe = "reflect"
      And s.ray.direction = comps.reflectv

  # --- the book's lights, seen from a diffuse hit: direct_light(w, comps, weight, bounce)

  # The book's diffuse term: weight (colour times diffuse) times intensity times the
  # cosine, so a point light is as bright under either integrator.
  @chapter21
  Scenario Outline: A point light lights a diffuse hit by the cosine, unless shadowed
    Given w ← world()
      And floor ← plane()
      And floor is added to w
      And w.light ← point_light(<position>, color(1, 1, 1))
      And r ← ray(point(0, 1, -1), vector(0, -√2/2, √2/2))
      And i ← intersection(√2, floor)
    When comps ← prepare_computations(i, r)
    Then direct_light(w, comps, color(0.5, 0.5, 0.5), 0) = <result>

    Examples:
      | position         | result                           |
      | point(0, 10, 0)  | color(0.5, 0.5, 0.5)             |
      | point(10, 10, 0) | color(0.35355, 0.35355, 0.35355) |
      | point(0, -10, 0) | color(0, 0, 0)                   |

  @chapter21
  Scenario: Something between a diffuse hit and the light shadows it
    Given w ← world()
      And floor ← plane()
      And ball ← sphere() with:
        | transform | translation(0, 5, 0) |
      And floor is added to w
      And ball is added to w
      And w.light ← point_light(point(0, 10, 0), color(1, 1, 1))
      And r ← ray(point(0, 1, -1), vector(0, -√2/2, √2/2))
      And i ← intersection(√2, floor)
    When comps ← prepare_computations(i, r)
    Then direct_light(w, comps, color(0.5, 0.5, 0.5), 0) = color(0, 0, 0)

  # An area light is sampled at one point spread over the whole of it; a small one far
  # above lights the hit as a point light at its centre would.
  @chapter21
  Scenario: An area light lights a diffuse hit from one point on it
    Given w ← world()
      And floor ← plane()
      And floor is added to w
      And w.light ← area_light(point(-0.001, 10, -0.001), vector(0.002, 0, 0), 4, vector(0, 0, 0.002), 4, color(1, 1, 1))
      And r ← ray(point(0, 1, -1), vector(0, -√2/2, √2/2))
      And i ← intersection(√2, floor)
    When comps ← prepare_computations(i, r)
    Then direct_light(w, comps, color(0.5, 0.5, 0.5), 0) = color(0.5, 0.5, 0.5)

  # --- a path: path_color_at(w, r, depth, roulette, bounce, throughput)

  @chapter21
  Scenario: A path sees what a surface emits
    Given w ← world()
      And shape ← sphere() with:
        | material.emissive | color(1, 0.5, 0.25) |
        | material.diffuse  | 0                   |
      And shape is added to w
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
    Then path_color_at(w, r) = color(1, 0.5, 0.25)
      And path_color_at(w, r, 5, 0, 2, color(0.5, 0.5, 0.5)) = color(0.5, 0.25, 0.125)

  # The book's integrator keeps its black background and knows nothing of emission.
  @chapter21
  Scenario: The book's integrator ignores the sky and emission
    Given w ← world()
      And shape ← sphere() with:
        | material.emissive | color(1, 0.5, 0.25) |
      And shape is added to w
      And w.sky ← sky(color(0.5, 0.5, 0.5))
    Then color_at(w, ray(point(0, 0, -5), vector(0, 0, 1))) = color(0, 0, 0)
      And color_at(w, ray(point(0, 0, -5), vector(0, 1, 0))) = color(0, 0, 0)

  @chapter21
  Scenario Outline: A path that meets nothing sees a uniform sky
    Given w ← world()
      And w.sky ← sky(color(0.2, 0.4, 0.6))
    Then path_color_at(w, ray(point(1, 2, 3), <direction>)) = color(0.2, 0.4, 0.6)

    Examples:
      | direction        |
      | vector(0, 1, 0)  |
      | vector(0, -1, 0) |
      | vector(1, 0, 0)  |
      | vector(1, 2, -3) |

  @chapter21
  Scenario: A world without a sky is black all around
    Given w ← world()
    Then w.sky is nothing
      And path_color_at(w, ray(point(0, 0, 0), vector(0, 1, 0))) = color(0, 0, 0)

  # From the horizon (and below it) to the zenith, by the height of the direction.
  @chapter21
  Scenario Outline: A gradient sky
    Given s ← gradient_sky(color(1, 1, 1), color(0.5, 0.7, 1.0))
    Then sky_color(s, <direction>) = <result>

    Examples:
      | direction        | result                       |
      | vector(0, 1, 0)  | color(0.5, 0.7, 1.0)         |
      | vector(0, 3, 0)  | color(0.5, 0.7, 1.0)         |
      | vector(1, 0, 0)  | color(1, 1, 1)               |
      | vector(0, -1, 0) | color(1, 1, 1)               |
      | vector(1, 1, 0)  | color(0.64645, 0.78787, 1.0) |

  # A black surface takes every bit of light that reaches it: the path ends there, with
  # only what the surface itself emits.
  @chapter21
  Scenario: A black diffuse surface returns only its emission
    Given w ← world()
      And shape ← sphere() with:
        | material.color    | color(0, 0, 0)       |
        | material.emissive | color(0.1, 0.2, 0.3) |
      And shape is added to w
      And w.light ← point_light(point(-10, 10, -10), color(1, 1, 1))
      And w.sky ← sky(color(1, 1, 1))
    Then path_color_at(w, ray(point(0, 0, -5), vector(0, 0, 1))) = color(0.1, 0.2, 0.3)

  # At the hit of bounce `depth` only emission counts: depth 0 shows the emitters alone,
  # depth 1 adds direct light and one bounce.
  @chapter21
  Scenario: The bounce cap
    Given w ← world()
      And floor ← plane() with:
        | material.color   | color(1, 1, 1) |
        | material.diffuse | 0.5            |
      And floor is added to w
      And w.light ← point_light(point(0, 10, 0), color(1, 1, 1))
      And r ← ray(point(0, 1, -1), vector(0, -√2/2, √2/2))
    Then path_color_at(w, r, 0) = color(0, 0, 0)
      And path_color_at(w, r, 1) = color(0.5, 0.5, 0.5)
      And path_color_at(w, r, 5) = color(0.5, 0.5, 0.5)

  # Under the book's light and a black sky, the two integrators agree on a diffuse floor.
  @chapter21
  Scenario: Path tracing and the book agree on directly lit diffuse surfaces
    Given w ← world()
      And floor ← plane() with:
        | material.color    | color(1, 0.5, 0.25) |
        | material.diffuse  | 0.8                 |
        | material.ambient  | 0                   |
        | material.specular | 0                   |
      And floor is added to w
      And w.light ← point_light(point(3, 10, -2), color(1, 1, 1))
      And r ← ray(point(0, 1, -1), vector(0, -√2/2, √2/2))
    Then path_color_at(w, r) = color_at(w, r)

  # The white furnace: a sphere that reflects all the light it gets (colour 1, diffuse 1)
  # under a uniform sky returns exactly the sky along every path: it vanishes.
  @chapter21
  Scenario Outline: A white diffuse sphere vanishes in a uniform sky
    Given w ← world()
      And shape ← sphere() with:
        | material.color   | color(1, 1, 1) |
        | material.diffuse | 1              |
      And shape is added to w
      And w.sky ← sky(color(0.5, 0.5, 0.5))
    Then path_color_at(w, ray(<origin>, <direction>), <depth>) = color(0.5, 0.5, 0.5)

    Examples:
      | origin            | direction        | depth |
      | point(0, 0, -5)   | vector(0, 0, 1)  | 1     |
      | point(0, 0, -5)   | vector(0, 0, 1)  | 5     |
      | point(0, 0.9, -5) | vector(0, 0, 1)  | 5     |
      | point(0, 5, 0)    | vector(0, -1, 0) | 3     |
      | point(0, 0, -5)   | vector(0, 1, 0)  | 5     |

  # Lossless glass (nothing of it is diffuse) vanishes as well, head on.
  @chapter21
  Scenario: A clear glass sphere vanishes in a uniform sky
    Given w ← world()
      And shape ← glass_sphere()
      And shape is added to w
      And w.sky ← sky(color(0.5, 0.5, 0.5))
    Then path_color_at(w, ray(point(0, 0, -5), vector(0, 0, 1))) = color(0.5, 0.5, 0.5)

  # A mirror shows the sky in the direction it reflects to.
  @chapter21
  Scenario Outline: A mirror shows the sky
    Given w ← world()
      And shape ← sphere() with:
        | material.reflective | 1 |
      And shape is added to w
      And w.sky ← gradient_sky(color(1, 1, 1), color(0.5, 0.7, 1.0))
    Then path_color_at(w, ray(<origin>, <direction>)) = <result>

    Examples:
      | origin          | direction        | result               |
      | point(0, 0, -5) | vector(0, 0, 1)  | color(1, 1, 1)       |
      | point(0, 5, 0)  | vector(0, -1, 0) | color(0.5, 0.7, 1.0) |

  # --- Russian roulette: russian_roulette(throughput, u)

  # From the roulette bounce on, a path goes on with the probability p of its brightest
  # channel (at most 1), its throughput divided by p: unbiased, and a dim path ends early.
  @chapter21
  Scenario Outline: Russian roulette keeps a path with the probability of its throughput
    Then russian_roulette(<throughput>, <u>) = <result>

    Examples:
      | throughput            | u    | result             |
      | color(0.25, 0.1, 0.2) | 0.2  | color(1, 0.4, 0.8) |
      | color(0.25, 0.1, 0.2) | 0.25 | color(0, 0, 0)     |
      | color(0.25, 0.1, 0.2) | 0.9  | color(0, 0, 0)     |
      | color(2, 0.5, 0)      | 0.99 | color(2, 0.5, 0)   |
      | color(0, 0, 0)        | 0    | color(0, 0, 0)     |

  # A white path always survives, so the furnace stays exact with roulette on.
  @chapter21
  Scenario: Russian roulette leaves the white furnace exact
    Given w ← world()
      And shape ← sphere() with:
        | material.color   | color(1, 1, 1) |
        | material.diffuse | 1              |
      And shape is added to w
      And w.sky ← sky(color(0.5, 0.5, 0.5))
    Then path_color_at(w, ray(point(0, 0, -5), vector(0, 0, 1)), 5, 1) = color(0.5, 0.5, 0.5)
