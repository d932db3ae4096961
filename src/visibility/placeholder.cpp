// Stage placeholder until the stage's first source lands.
